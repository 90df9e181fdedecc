// One vehicle's adaptation on the ground (groundstation/runtime/vehicle_adaptation.hpp): its
// measured thrust gain divides its setpoints, its poses judge its pole filter's trust once a
// period, what identification keeps is set on board at arming and counts once acknowledged, and
// a drifted on-board attitude is sent back as CORRECT_TILT.
#include <catch2/catch.hpp>

#include <cmath>
#include <optional>
#include <vector>

#include "adaptation_test_support.hpp"
#include "groundstation/runtime/thrust_compensation.hpp"
#include "groundstation/runtime/vehicle_adaptation.hpp"

namespace {

using gs::link::CommandHandle;
using gs::link::CommandState;
using gs::mission::Task;
using gs::runtime::OnBoardCommand;
using gs::runtime::VehicleAdaptation;
using gs::runtime::VehicleAdaptationSettings;
using pa::proto::CommandCode;

VehicleAdaptationSettings settings(bool compensate = true) {
  VehicleAdaptationSettings s;
  s.compensate_thrust_gain = compensate;
  s.limits = {1.0, 20.0, 10.0};
  s.airframe_thrust_max_mps2 = 24.6;
  s.pole_weight_mps2 = 0.57;
  return s;
}

gs::estimation::MocapPose hovering_pose() {
  gs::estimation::MocapPose pose;
  pose.p_m.z() = 1.0;
  return pose;
}

// Two seconds of hover at 1 m on a commanded g / 0.8: a vehicle that delivers 0.8 of it.
void hover_on_a_weak_vehicle(VehicleAdaptation& a) {
  for (int i = 0; i < 400; ++i) {
    const double t = 0.005 * i;
    gs::model::VehicleInput sent;
    sent.a_q_mps2 = 9.81 / 0.8;
    a.delivered(sent, t, t);
    a.on_pose(t, t, hovering_pose(), Task::hover);
  }
}

gs::estimation::IdentificationResult slow_and_heavy() {
  gs::estimation::MotorIdentification m;
  m.time_constant_s = 0.045;
  m.time_constant_low_s = 0.044;
  m.time_constant_high_s = 0.046;
  m.inertia_gain = 1.25;
  m.round_trip_s = 0.021;
  m.rms_radps = 0.04;
  m.samples = 260;
  return {gs::estimation::IdentificationRefusal::none, m};
}

}  // namespace

TEST_CASE(
    "The measured gain divides the setpoint's thrust, and the estimator is told what the vehicle delivers") {
  VehicleAdaptation a(pa::kVehicle1, settings());
  gs::model::VehicleInput law;
  law.a_q_mps2 = 9.81;
  law.omega_radps = Eigen::Vector3d(0.1, -0.2, 0.3);
  // Before any measurement the gain is 1: the law's input goes out as it is.
  CHECK(a.setpoint(law, 0.0).a_q_mps2 == 9.81);
  CHECK(a.setpoint(law, 0.0).omega_radps == law.omega_radps);  // no identification flying

  hover_on_a_weak_vehicle(a);
  const double k = a.thrust_gain().gain();
  REQUIRE(a.thrust_gain().measurements() > 0);
  REQUIRE(k < 0.9);
  const gs::model::VehicleInput sent = a.setpoint(law, 2.0);
  CHECK(sent.a_q_mps2 == gs::runtime::compensated_thrust_mps2(9.81, k, settings().limits, 24.6));
  CHECK(sent.a_q_mps2 > 9.81 / 0.9);
  // What the vehicle makes of it is what the law asked for.
  CHECK(a.delivered(sent, 2.0, 2.012).a_q_mps2 == Approx(9.81));

  // Not compensated: the gain is measured and used nowhere, the law's thrust goes out and the
  // estimator's model takes it as delivered.
  VehicleAdaptation raw(pa::kVehicle2, settings(false));
  hover_on_a_weak_vehicle(raw);
  REQUIRE(raw.thrust_gain().gain() < 0.9);
  CHECK(raw.setpoint(law, 2.0).a_q_mps2 == 9.81);
  CHECK(raw.delivered(raw.setpoint(law, 2.0), 2.0, 2.012).a_q_mps2 == 9.81);
}

TEST_CASE("Poses judge the pole filter's trust once a period, from the motor lag set on board") {
  VehicleAdaptation a(pa::kVehicle1, settings());
  const gs::estimation::PoleTrust trust;
  const std::optional<double> first = a.on_pose(0.0, 0.0, hovering_pose(), Task::hover);
  REQUIRE(first);
  // No noise measured yet: the airframe's lag, quiet poses.
  CHECK(*first == gs::estimation::pole_measurement_sigma(0.03, std::nan(""), trust));
  int judged = 0;
  for (int i = 1; i <= 400; ++i) {  // two more seconds at 200 Hz
    const double t = 0.005 * i;
    if (a.on_pose(t, t, hovering_pose(), Task::hover)) ++judged;
  }
  CHECK(judged == 2);  // at 1 s and 2 s
}

TEST_CASE("What identification keeps is set at arming, and counts on board once acknowledged") {
  gs::adaptation::IdentificationMemory memory({0.03, 0.1}, "", adaptation_test::nominal_settings());
  VehicleAdaptation a(pa::kVehicle1, settings());
  CHECK(a.at_arming(memory).empty());                          // nothing kept: the firmware's own
  CHECK(a.identify(1.0, Task::hover, false, memory).empty());  // no flight flown

  memory.finished(pa::kVehicle1, slow_and_heavy(), std::nullopt, 1.0, 0.03);
  const std::vector<OnBoardCommand> commands = a.at_arming(memory);
  REQUIRE(commands.size() == 2);
  CHECK(commands[0].code == CommandCode::set_motor_time_constant);
  CHECK(commands[0].argument == 45000);
  CHECK(commands[0].value == 0.045);
  CHECK(commands[1].code == CommandCode::set_inertia_scale);
  CHECK(commands[1].argument == 800);
  CHECK(commands[1].value == Approx(0.8));
  CHECK(VehicleAdaptation(pa::kVehicle2, settings()).at_arming(memory).empty());  // each its own

  a.sent(commands[0], CommandHandle{pa::kVehicle1, 1, 1});
  a.sent(commands[1], CommandHandle{pa::kVehicle1, 2, 2});
  // The lag acknowledged, the inertia's still in flight.
  a.settle(
      [](const CommandHandle& h) { return h.serial == 1 ? CommandState::accepted : CommandState::pending; });
  CHECK(a.motors().equalised_s() == 0.045);
  CHECK(a.motors().inertia_scale() == 1.0);
  // The inertia's refused: the file's stays.
  a.settle([](const CommandHandle&) { return CommandState::refused; });
  CHECK(a.motors().inertia_scale() == 1.0);
  CHECK(a.motors().equalised_s() == 0.045);
  // A CORRECT_TILT sets neither.
  a.sent(OnBoardCommand{CommandCode::correct_tilt, 0, 0.0}, CommandHandle{pa::kVehicle1, 3, 3});
  a.settle([](const CommandHandle&) { return CommandState::accepted; });
  CHECK(a.motors().equalised_s() == 0.045);
  CHECK(a.motors().inertia_scale() == 1.0);
}

TEST_CASE("An on-board attitude drifted from motion capture's goes back as CORRECT_TILT") {
  VehicleAdaptation a(pa::kVehicle1, settings());
  gs::estimation::OnboardTilt reference;
  const Eigen::Quaterniond measured = Eigen::Quaterniond::Identity();
  const Eigen::Quaterniond onboard(Eigen::AngleAxisd(0.03, Eigen::Vector3d::UnitX()));
  int corrections = 0;
  for (int k = 0; k < 300; ++k) {  // 3 s of reports every 10 ms
    const double t_s = 0.01 * k;
    const std::optional<Eigen::Vector2d> up = reference.report(t_s, onboard, measured, 0.2);
    const std::optional<OnBoardCommand> command = a.tilt_correction(t_s, onboard, measured, 0.2);
    REQUIRE(command.has_value() == up.has_value());
    if (!command) continue;
    ++corrections;
    CHECK(command->code == CommandCode::correct_tilt);
    CHECK(command->argument == gs::estimation::tilt_correction_argument(*up));
  }
  CHECK(corrections >= 1);
}
