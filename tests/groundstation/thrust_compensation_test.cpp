// The thrust gain's part in the setpoints (groundstation/runtime/thrust_compensation.hpp): which
// poses measure it, with what load, and the thrust a setpoint carries.
#include <catch2/catch.hpp>

#include "groundstation/runtime/thrust_compensation.hpp"

namespace {

using gs::mission::Task;
using gs::runtime::compensated_thrust_mps2;
using gs::runtime::thrust_gain_sample;

const gs::model::VehicleLimits kLimits{1.0, 20.0, 10.0};

}  // namespace

TEST_CASE("The gain is measured flying on thrust alone, above the floor; balancing with the pole's weight") {
  for (Task t : {Task::take_off, Task::hover, Task::wait, Task::retreat, Task::clear, Task::balance}) {
    CAPTURE(gs::mission::task_name(t));
    CHECK(thrust_gain_sample(t, 1.0, 0.3, 0.57).steady);
    CHECK_FALSE(thrust_gain_sample(t, 0.3, 0.3, 0.57).steady);  // at the floor's height: not
    CHECK(thrust_gain_sample(t, 1.0, 0.3, 0.57).load_mps2 == (t == Task::balance ? 0.57 : 0.0));
  }
  for (Task t : {Task::parked, Task::arming, Task::throwing, Task::release, Task::catching, Task::rebalance,
                 Task::landing, Task::failsafe}) {
    CAPTURE(gs::mission::task_name(t));
    CHECK_FALSE(thrust_gain_sample(t, 1.0, 0.3, 0.57).steady);
  }
}

TEST_CASE("The setpoint carries a_q / k: the laws' a_q within the limits, the motors up to full thrust") {
  const double kFull = 24.6;
  CHECK(compensated_thrust_mps2(9.0, 0.9, kLimits, kFull) == Approx(10.0));
  CHECK(compensated_thrust_mps2(9.81, 1.0, kLimits, kFull) == 9.81);
  CHECK(compensated_thrust_mps2(19.0, 0.8, kLimits, kFull) == Approx(23.75));  // beyond a_q,max: the motors'
  CHECK(compensated_thrust_mps2(22.0, 0.8, kLimits, kFull) == kFull);          // a_full at most
  CHECK(compensated_thrust_mps2(22.0, 1.0, kLimits, kFull) == 20.0);           // the laws ask a_q,max at most
  CHECK(compensated_thrust_mps2(0.5, 1.2, kLimits, kFull) == 1.0);             // the minimum
  CHECK(compensated_thrust_mps2(0.0, 0.8, kLimits, kFull) == 0.0);             // ARM's zero thrust
}
