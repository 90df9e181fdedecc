// A catch as the vehicle handles it on its own: the window the ground station announces
// (EXPECT_CATCH) in which an impact is classed a catch, and the reaction after one (extra thrust
// for the pole's weight, optionally levelling) until the ground takes over (CATCH_HANDLED) or
// the reaction times out. Header only and inline: tick() calls it every millisecond (catch_reaction_test.cpp). No heap,
// constant time, wrap-safe on the 32-bit microsecond clock.
#pragma once

#include <cstdint>

#include "fw/config.hpp"
#include "pa/sequence.hpp"

namespace fw {

class CatchReaction {
 public:
  explicit CatchReaction(const CatchReactionConfig& config) : config_(config) {}

  // EXPECT_CATCH accepted at `now_us`: a catch is expected for `window_ms`.
  void expect(std::uint32_t now_us, std::uint32_t window_ms) {
    expected_ = true;
    expected_until_us_ = now_us + window_ms * 1000u;
  }
  // An impact classed a catch at `now_us`: the reaction starts, and the window closes (one catch
  // per window). A catch during a reaction changes nothing.
  void on_catch(std::uint32_t now_us) {
    if (active_) return;
    active_ = true;
    started_us_ = now_us;
    expected_ = false;
  }
  // CATCH_HANDLED: the ground station flies the catch on from here.
  void handled() { active_ = false; }
  // Once a tick: the window closes and the reaction ends by themselves.
  void update(std::uint32_t now_us) {
    if (expected_ && pa::elapsed_us(now_us, expected_until_us_) > 0) expected_ = false;
    if (active_ && pa::elapsed_us(now_us, started_us_) >= static_cast<std::int32_t>(config_.duration_us))
      active_ = false;
  }

  bool expected() const { return expected_; }
  bool active() const { return active_; }
  // While active, added to the ground's thrust setpoint; and whether its rates give way to levelling.
  float thrust_add_mps2() const { return config_.thrust_add_mps2; }
  bool hold_level() const { return config_.hold_level; }

 private:
  CatchReactionConfig config_;
  std::uint32_t expected_until_us_ = 0;
  bool expected_ = false;
  bool active_ = false;
  std::uint32_t started_us_ = 0;
};

}  // namespace fw
