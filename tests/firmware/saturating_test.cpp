// The telemetry's saturating casts and counters.
#include <catch2/catch.hpp>

#include <cstdint>

#include "fw/saturating.hpp"

TEST_CASE("a saturating cast keeps what fits and reads the maximum for what does not") {
  CHECK(fw::saturate_cast<std::uint8_t>(std::uint32_t{254}) == 254);
  CHECK(fw::saturate_cast<std::uint8_t>(std::uint32_t{255}) == 255);
  CHECK(fw::saturate_cast<std::uint8_t>(std::uint32_t{256}) == 255);  // not 0
  CHECK(fw::saturate_cast<std::uint16_t>(std::uint32_t{65536 + 3}) == 0xFFFFu);
  CHECK(fw::saturate_cast<std::uint32_t>(std::uint64_t{0xFFFFFFFFu} + 1u) == 0xFFFFFFFFu);
  CHECK(fw::saturate_cast<std::uint32_t>(std::uint16_t{0xFFFFu}) == 0xFFFFu);  // widening
  static_assert(fw::saturate_cast<std::uint16_t>(std::uint32_t{70000}) == 0xFFFFu);
}

TEST_CASE("a saturating counter stops at its maximum") {
  std::uint8_t c = 253;
  fw::saturating_increment(c);
  CHECK(c == 254);
  fw::saturating_increment(c);
  fw::saturating_increment(c);
  CHECK(c == 255);
  std::uint32_t d = 0xFFFFFFFEu;
  fw::saturating_increment(d);
  fw::saturating_increment(d);
  CHECK(d == 0xFFFFFFFFu);
}
