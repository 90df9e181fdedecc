// The catch window and the on-board reaction (firmware/core/include/fw/catch_reaction.hpp): a
// window that closes by itself, one catch per window, a reaction that ends on CATCH_HANDLED or
// times out, across the 32-bit clock's wrap.
#include <catch2/catch.hpp>

#include <cstdint>

#include "fw/catch_reaction.hpp"

namespace {

fw::CatchReactionConfig config() {
  fw::CatchReactionConfig c;
  c.thrust_add_mps2 = 0.6f;
  c.hold_level = true;
  c.duration_us = 300000;
  return c;
}

}  // namespace

TEST_CASE("A catch is expected for the window announced, then not") {
  for (std::uint32_t start : {1000u, 0xFFFFFF00u}) {  // and across the clock's wrap
    CAPTURE(start);
    fw::CatchReaction c(config());
    CHECK_FALSE(c.expected());
    c.expect(start, 500);
    c.update(start + 500000u);
    CHECK(c.expected());  // up to its end
    c.update(start + 500001u);
    CHECK_FALSE(c.expected());
  }
}

TEST_CASE("A catch starts the reaction and closes the window; the reaction ends by itself") {
  for (std::uint32_t start : {1000u, 0xFFFFFF00u}) {
    CAPTURE(start);
    fw::CatchReaction c(config());
    c.expect(start, 2000);
    c.on_catch(start + 100u);
    CHECK(c.active());
    CHECK_FALSE(c.expected());  // one catch per window
    c.update(start + 100u + 299999u);
    CHECK(c.active());
    c.update(start + 100u + 300000u);
    CHECK_FALSE(c.active());
  }
}

TEST_CASE("A second catch during the reaction does not restart it; CATCH_HANDLED ends it") {
  fw::CatchReaction c(config());
  c.on_catch(0);
  c.on_catch(200000);
  c.update(300000);
  CHECK_FALSE(c.active());  // timed from the first
  c.on_catch(400000);
  CHECK(c.active());
  c.handled();
  CHECK_FALSE(c.active());
  CHECK(c.thrust_add_mps2() == 0.6f);
  CHECK(c.hold_level());
}
