#include <catch2/catch.hpp>

#include "pa/cli/arguments.hpp"

using pa::cli::parseNumber;
using pa::cli::parseCount;
using pa::cli::parseNumberPair;

TEST_CASE("numbers parse only when the whole text is a finite number", "[cli]") {
  CHECK(parseNumber("1.5") == 1.5);
  CHECK(parseNumber("-2e-3") == -2e-3);
  CHECK(parseNumber("0") == 0.0);
  CHECK_FALSE(parseNumber(""));
  CHECK_FALSE(parseNumber("1.5m"));
  CHECK_FALSE(parseNumber(" "));
  CHECK_FALSE(parseNumber("abc"));
  CHECK_FALSE(parseNumber("nan"));
  CHECK_FALSE(parseNumber("inf"));
  CHECK_FALSE(parseNumber("1e999"));
}

TEST_CASE("pairs parse as two numbers around one comma", "[cli]") {
  const auto p = parseNumberPair("0.25,-1");
  REQUIRE(p);
  CHECK(p->first == 0.25);
  CHECK(p->second == -1.0);
  CHECK_FALSE(parseNumberPair("0.25"));
  CHECK_FALSE(parseNumberPair("0.25,"));
  CHECK_FALSE(parseNumberPair(",1"));
  CHECK_FALSE(parseNumberPair("1,2,3"));
}

TEST_CASE("counts are decimal digits within 64 bits", "[cli]") {
  CHECK(parseCount("0") == 0u);
  CHECK(parseCount("100") == 100u);
  CHECK(parseCount("18446744073709551615") == UINT64_MAX);
  CHECK_FALSE(parseCount("18446744073709551616"));
  CHECK_FALSE(parseCount(""));
  CHECK_FALSE(parseCount("-1"));
  CHECK_FALSE(parseCount("1e3"));
  CHECK_FALSE(parseCount("12x"));
}
