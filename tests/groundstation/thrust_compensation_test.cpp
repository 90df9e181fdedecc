// The thrust gain's part in the setpoints (groundstation/runtime/thrust_compensation.hpp): which
// poses measure it, with what load, and the thrust a setpoint carries.
#include <catch2/catch.hpp>

#include "groundstation/runtime/thrust_compensation.hpp"

namespace {

using gs::mission::Task;
using gs::runtime::compensated_thrust_mps2;
using gs::runtime::measure_thrust_gain;
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
                 Task::landing, Task::failsafe, Task::descend}) {
    CAPTURE(gs::mission::task_name(t));
    CHECK_FALSE(thrust_gain_sample(t, 1.0, 0.3, 0.57).steady);
  }
}

namespace {

// A vehicle holding 1 m on a_q for 2 s in `task`, its poses to measure_thrust_gain: its gain as
// estimated.
gs::estimation::ThrustGainEstimator hold(Task task, double a_q_mps2, double height_m = 1.0) {
  gs::estimation::ThrustGainEstimator gain;
  gs::estimation::MocapPose pose;
  pose.p_m.z() = height_m;
  for (int i = 0; i < 400; ++i) {
    const double t = 0.005 * i;
    gain.command(t, a_q_mps2);
    measure_thrust_gain(gain, task, t, pose, 0.3, 0.57);
  }
  return gain;
}

}  // namespace

TEST_CASE("Poses measure the gain as thrust_gain_sample says, with the balanced pole's load") {
  // Hovering on g / 0.8 the vehicle delivers 0.8 of what it is commanded.
  const auto hovering = hold(Task::hover, 9.81 / 0.8);
  CHECK(hovering.measurements() > 0);
  CHECK(hovering.gain() < 0.9);
  // Balancing, the same command also holds the pole's weight: a gain nearer 1 + 0.57 / 9.81.
  const auto balancing = hold(Task::balance, 9.81 / 0.8);
  CHECK(balancing.measurements() > 0);
  CHECK(balancing.gain() > hovering.gain());
  // Throwing, or on the floor: no measurement.
  CHECK(hold(Task::throwing, 9.81 / 0.8).measurements() == 0);
  CHECK(hold(Task::hover, 9.81 / 0.8, 0.2).measurements() == 0);
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
