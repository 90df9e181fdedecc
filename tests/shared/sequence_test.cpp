#include <catch2/catch.hpp>

#include "pa/sequence.hpp"

TEST_CASE("a 4-bit setpoint sequence is newer up to half the space ahead, across the wrap") {
  using S = pa::SetpointSeq;
  for (std::uint32_t ref = 0; ref < 16; ++ref) {
    for (std::uint32_t ahead = 0; ahead < 16; ++ahead) {
      const std::uint32_t cand = (ref + ahead) & S::mask;
      CHECK(S::is_newer(cand, ref) == (ahead >= 1 && ahead <= 7));
    }
  }
  CHECK(S::next(15) == 0);
  CHECK(S::distance(14, 2) == 4);
}

TEST_CASE("an 8-bit sequence repeats are never newer and replays from behind are rejected") {
  using S = pa::CommandSeq;
  CHECK_FALSE(S::is_newer(100, 100));
  CHECK(S::is_newer(101, 100));
  CHECK(S::is_newer(0, 255));
  CHECK(S::is_newer(127, 0));
  CHECK_FALSE(S::is_newer(128, 0));
  CHECK_FALSE(S::is_newer(99, 100));
}

TEST_CASE("elapsed time is right across the 32-bit microsecond wrap") {
  CHECK(pa::elapsed_us(5, 0xFFFFFFFBu) == 10);
  CHECK(pa::elapsed_us(0xFFFFFFFBu, 5) == -10);
  CHECK(pa::elapsed_us(1000, 1000) == 0);
}
