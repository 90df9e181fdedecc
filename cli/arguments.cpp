#include "pa/cli/arguments.hpp"

#include <cmath>
#include <cstdlib>
#include <string>

namespace pa::cli {

std::optional<double> parseNumber(std::string_view text) {
  if (text.empty()) return std::nullopt;
  const std::string s(text);  // strtod needs the terminator
  char* end = nullptr;
  const double value = std::strtod(s.c_str(), &end);
  if (end != s.c_str() + s.size() || !std::isfinite(value)) return std::nullopt;
  return value;
}

std::optional<std::uint64_t> parseCount(std::string_view text) {
  if (text.empty()) return std::nullopt;
  std::uint64_t value = 0;
  for (const char c : text) {
    if (c < '0' || c > '9') return std::nullopt;
    const auto digit = static_cast<std::uint64_t>(c - '0');
    if (value > (UINT64_MAX - digit) / 10) return std::nullopt;
    value = value * 10 + digit;
  }
  return value;
}

std::optional<NumberPair> parseNumberPair(std::string_view text) {
  const std::size_t comma = text.find(',');
  if (comma == std::string_view::npos) return std::nullopt;
  const std::optional<double> a = parseNumber(text.substr(0, comma));
  const std::optional<double> b = parseNumber(text.substr(comma + 1));
  if (!a || !b) return std::nullopt;
  return NumberPair{*a, *b};
}

}  // namespace pa::cli
