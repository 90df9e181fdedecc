// The ground station's estimates as the telemetry topics carry them
// (groundstation/dds/telemetry_conversion.hpp).
#include "groundstation/dds/telemetry_conversion.hpp"

#include <catch2/catch.hpp>

#include "groundstation/estimation/mocap_pose.hpp"

using gs::estimation::PoleMode;

TEST_CASE("A vehicle's attitude becomes the quaternion of its zyx Euler angles", "[dds]") {
  gs::estimation::VehicleEstimate e;
  e.state.p_m = Eigen::Vector3d(1.0, 2.0, 3.0);
  e.state.v_mps = Eigen::Vector3d(0.1, 0.2, 0.3);
  e.state.phi_rad = 0.2;
  e.state.theta_rad = -0.3;
  e.state.psi_rad = 2.5;
  e.body_rates_radps = Eigen::Vector3d(0.4, 0.5, 0.6);

  const gs::link::VehicleLinkStatus status;
  const auto m = gs::dds::vehicle_telemetry_to_ros(pa::kVehicle1, 0, status, gs::mission::Task::hover, e);
  CHECK(m.position.x == 1.0);
  CHECK(m.position.z == 3.0);
  CHECK(m.velocity.y == 0.2);
  CHECK(m.body_rate.x == 0.4);
  CHECK(m.body_rate.z == 0.6);
  // ROS's quaternion is (x, y, z, w).
  const Eigen::Quaterniond q(m.orientation.w, m.orientation.x, m.orientation.y, m.orientation.z);
  CHECK(q.norm() == Approx(1.0));
  CHECK(q.isApprox(gs::dds::vehicle_attitude(e.state)));
  const auto angles = gs::estimation::euler_zyx_from_quaternion(q);
  CHECK(angles.phi_rad == Approx(0.2));
  CHECK(angles.theta_rad == Approx(-0.3));
  CHECK(angles.psi_rad == Approx(2.5));
}

TEST_CASE("The link state follows the heartbeats", "[dds]") {
  gs::link::VehicleLinkStatus status;
  status.heard = false;
  CHECK(gs::dds::link_state_to_ros(status) == gs::dds::link_state::kUnheard);
  status.heard = true;
  status.lost = false;
  CHECK(gs::dds::link_state_to_ros(status) == gs::dds::link_state::kUp);
  status.lost = true;
  CHECK(gs::dds::link_state_to_ros(status) == gs::dds::link_state::kLost);
}

TEST_CASE("A vehicle's telemetry carries its id, task, reported mode and estimate", "[dds]") {
  gs::link::VehicleLinkStatus status;
  status.heard = true;
  status.lost = false;
  status.mode = pa::proto::Mode::flying;
  gs::estimation::VehicleEstimate e;
  e.state.p_m = Eigen::Vector3d(0.0, 0.0, 1.0);

  const auto t = gs::dds::vehicle_telemetry_to_ros(pa::kVehicle2, 1'700'000'002'500'000'000, status,
                                                   gs::mission::Task::hover, e);
  CHECK(t.vehicle == 2);
  CHECK(t.stamp.sec == 1'700'000'002);
  CHECK(t.stamp.nanosec == 500'000'000u);
  CHECK(t.link == gs::dds::link_state::kUp);
  // The .msg file's constants name the task and the mode (ROS 2 tools show them by those names).
  CHECK(t.task == pa_msgs_msg_VehicleTelemetry_Constants_TASK_HOVER);
  CHECK(t.vehicle_mode == pa_msgs_msg_VehicleTelemetry_Constants_MODE_FLYING);
  CHECK(t.estimate_valid);
  CHECK(t.position.z == 1.0);

  const auto none =
      gs::dds::vehicle_telemetry_to_ros(pa::kVehicle1, 0, status, gs::mission::Task::parked, {});
  CHECK(none.vehicle == 1);
  CHECK(none.task == pa_msgs_msg_VehicleTelemetry_Constants_TASK_PARKED);
  CHECK_FALSE(none.estimate_valid);
  CHECK(none.position.z == 0.0);
}

TEST_CASE("Pole modes map both ways, and a value no mode has is none", "[dds]") {
  for (const PoleMode mode : gs::estimation::kPoleModes) {
    CHECK(gs::dds::pole_mode_from_ros(gs::dds::pole_mode_to_ros(mode)) == mode);
  }
  CHECK(gs::dds::pole_mode_to_ros(PoleMode::on_vehicle2) ==
        pa_msgs_msg_PoleTelemetry_Constants_POLE_ON_VEHICLE2);
  CHECK_FALSE(gs::dds::pole_mode_from_ros(3).has_value());
  CHECK_FALSE(gs::dds::pole_mode_from_ros(255).has_value());
}

TEST_CASE("The pole's telemetry carries its state and the catch forecast when there is one", "[dds]") {
  gs::estimation::PoleEstimate pole;
  pole.valid = true;
  pole.mode = PoleMode::free;
  pole.state.p_m = Eigen::Vector3d(0.1, 0.2, 3.0);
  pole.state.v_mps = Eigen::Vector3d(1.0, 0.0, 3.0);
  pole.state.n = Eigen::Vector3d(0.0, 0.6, 0.8);
  pole.state.omega_radps = Eigen::Vector3d(0.5, 0.0, 0.0);

  const auto without = gs::dds::pole_telemetry_to_ros(pole, 1'000'000'000);
  CHECK(without.estimate_valid);
  CHECK(without.stamp.sec == 1);
  CHECK(without.mode == gs::dds::pole_mode::kFree);
  CHECK_FALSE(without.catch_predicted);
  CHECK(without.catch_vehicle == 0);
  const gs::model::PoleState back = gs::dds::pole_state_from_ros(without);
  CHECK(back.p_m == pole.state.p_m);
  CHECK(back.v_mps == pole.state.v_mps);
  CHECK(back.n == pole.state.n);
  CHECK(back.omega_radps == pole.state.omega_radps);

  const gs::dds::CatchForecast forecast{1'600'000'000, Eigen::Vector3d(1.0, 0.1, 1.3), pa::kVehicle2};
  const auto with = gs::dds::pole_telemetry_to_ros(pole, 1'000'000'000, forecast);
  CHECK(with.catch_predicted);
  CHECK(with.catch_stamp.sec == 1);
  CHECK(with.catch_stamp.nanosec == 600'000'000u);
  CHECK(with.catch_point.x == 1.0);
  CHECK(with.catch_point.z == 1.3);
  CHECK(with.catch_vehicle == 2);
}
