// Parsing of command-line values: strict, so that a typo is an error and never a silent 0.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

namespace pa::cli {

// The whole of `text` as a finite number ("1.5", "-2e-3"); nullopt for "", "1.5m", "nan", "inf".
std::optional<double> parseNumber(std::string_view text);

// Decimal digits only ("100"); nullopt for "", "-1", "1e3", "12x" or beyond 2^64 - 1.
std::optional<std::uint64_t> parseCount(std::string_view text);

// "A,B" as two numbers; nullopt unless both parse.
struct NumberPair {
  double first = 0.0;
  double second = 0.0;
};
std::optional<NumberPair> parseNumberPair(std::string_view text);

}  // namespace pa::cli
