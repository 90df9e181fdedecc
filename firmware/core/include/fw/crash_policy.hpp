// When an impact classed a crash (impact_detector.hpp) stops the motors. Decided in a periodic
// task at 200 Hz, not in the impact's tick, to keep that tick short (crash_policy_test.cpp).
#pragma once

#include "fw/supervisor.hpp"

namespace fw {

// In `mode`, the attitude's tilt cosine being `tilt_cos`. On the floor, and flying under the
// ground's control, a crash stops the motors. In a hold or a failsafe the ground no longer
// steers: a crash class there is mostly the pole landing on a plate cut during its catch
// manoeuvre, or the floor met askew. A vehicle still upright keeps levelling and descending (the
// floor then lands it, motors off) rather than falling from the height of a catch; one tilted to
// `min_tilt_cos` or beyond is tumbling and is stopped.
constexpr bool crash_stops_motors(pa::proto::Mode mode, float tilt_cos, float min_tilt_cos) {
  return !on_board_flight(mode) || tilt_cos <= min_tilt_cos;
}

}  // namespace fw
