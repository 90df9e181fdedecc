// When an impact classed a crash (impact_detector.hpp) stops the motors. Decided in a periodic
// task at 200 Hz, not in the impact's tick, to keep that tick short (crash_policy_test.cpp).
#pragma once

#include "fw/supervisor.hpp"

namespace fw {

// In `mode`, the attitude's tilt cosine being `tilt_cos`. On the floor a crash stops the motors.
// In the air a crash class is mostly the pole: landing on a plate cut during its catch manoeuvre,
// a catch's own impact past the crash peak, a dropped pole falling onto the vehicle (270 m/s^2
// on a vehicle hovering at 2.6 m, whose motors then stopped: it fell; envelope campaign seed 2,
// attempts 361 and 844), or the floor met askew. A vehicle still upright flies on, under the ground's control or its own levelling
// and descent (the floor then lands it, motors off), rather than falling from the height of a
// catch; one tilted to `min_tilt_cos` or beyond is tumbling and is stopped.
// The modes in the air (flown from the ground, or on board: supervisor.hpp) as one mask, computed
// at compile time: the policy runs in the periodic task of the firmware's longest tick, whose
// budget (1500 instructions on the Cortex-M4) two tests would pass.
constexpr unsigned modes_in_the_air() {
  unsigned mask = 0;
  for (unsigned m = 0; m <= pa::proto::kModeMax; ++m) {
    const auto mode = static_cast<pa::proto::Mode>(m);
    if (action_for(mode) == Action::track_setpoints || on_board_flight(mode)) mask |= 1u << m;
  }
  return mask;
}
inline constexpr unsigned kModesInTheAir = modes_in_the_air();
constexpr bool crash_stops_motors(pa::proto::Mode mode, float tilt_cos, float min_tilt_cos) {
  return ((kModesInTheAir >> static_cast<unsigned>(mode)) & 1u) == 0 || tilt_cos <= min_tilt_cos;
}

}  // namespace fw
