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

  const pa_arena_Estimate m = gs::dds::vehicle_estimate_to_dds(e);
  CHECK(m.position_m.x == 1.0);
  CHECK(m.position_m.z == 3.0);
  CHECK(m.velocity_mps.y == 0.2);
  CHECK(m.rate_radps.x == 0.4);
  CHECK(m.rate_radps.z == 0.6);
  const Eigen::Quaterniond q(m.attitude.w, m.attitude.x, m.attitude.y, m.attitude.z);
  CHECK(q.norm() == Approx(1.0));
  const auto angles = gs::estimation::euler_zyx_from_quaternion(q);
  CHECK(angles.phi_rad == Approx(0.2));
  CHECK(angles.theta_rad == Approx(-0.3));
  CHECK(angles.psi_rad == Approx(2.5));
}

TEST_CASE("The link state follows the heartbeats", "[dds]") {
  gs::link::VehicleLinkStatus status;
  status.heard = false;
  CHECK(gs::dds::link_state_to_dds(status) == pa_arena_link_unheard);
  status.heard = true;
  status.lost = false;
  CHECK(gs::dds::link_state_to_dds(status) == pa_arena_link_up);
  status.lost = true;
  CHECK(gs::dds::link_state_to_dds(status) == pa_arena_link_lost);
}

TEST_CASE("A vehicle's telemetry carries its id, task, reported mode and estimate", "[dds]") {
  gs::link::VehicleLinkStatus status;
  status.heard = true;
  status.lost = false;
  status.mode = pa::proto::Mode::flying;
  gs::estimation::VehicleEstimate e;
  e.state.p_m = Eigen::Vector3d(0.0, 0.0, 1.0);

  const auto t = gs::dds::vehicle_telemetry_to_dds(pa::kVehicle2, 2.5, status, gs::mission::Task::hover, e);
  CHECK(t.vehicle == 2);
  CHECK(t.time_ns == 2'500'000'000);
  CHECK(t.link == pa_arena_link_up);
  CHECK(t.mode == static_cast<std::uint8_t>(gs::mission::Task::hover));
  CHECK(t.vehicle_mode == static_cast<std::uint8_t>(pa::proto::Mode::flying));
  CHECK(t.estimate_valid);
  CHECK(t.estimate.position_m.z == 1.0);

  const auto none =
      gs::dds::vehicle_telemetry_to_dds(pa::kVehicle1, 0.0, status, gs::mission::Task::parked, {});
  CHECK(none.vehicle == 1);
  CHECK_FALSE(none.estimate_valid);
}

TEST_CASE("Pole modes map both ways", "[dds]") {
  for (const PoleMode mode : gs::estimation::kPoleModes) {
    CHECK(gs::dds::pole_mode_from_dds(gs::dds::pole_mode_to_dds(mode)) == mode);
  }
  CHECK(gs::dds::pole_mode_to_dds(PoleMode::on_vehicle2) == pa_arena_pole_on_vehicle2);
}

TEST_CASE("The pole's state survives the conversion and back", "[dds]") {
  gs::model::PoleState s;
  s.p_m = Eigen::Vector3d(0.1, 0.2, 2.5);
  s.v_mps = Eigen::Vector3d(1.0, 0.0, 3.0);
  s.n = Eigen::Vector3d(0.0, 0.6, 0.8);
  s.omega_radps = Eigen::Vector3d(0.5, 0.0, 0.0);
  const gs::model::PoleState back = gs::dds::pole_state_from_dds(gs::dds::pole_state_to_dds(s));
  CHECK(back.p_m == s.p_m);
  CHECK(back.v_mps == s.v_mps);
  CHECK(back.n == s.n);
  CHECK(back.omega_radps == s.omega_radps);
}

TEST_CASE("The pole's telemetry carries the catch forecast when there is one", "[dds]") {
  gs::estimation::PoleEstimate pole;
  pole.valid = true;
  pole.mode = PoleMode::free;
  pole.state.p_m = Eigen::Vector3d(0.0, 0.0, 3.0);

  const auto without = gs::dds::pole_telemetry_to_dds(pole, 1.0);
  CHECK(without.estimate_valid);
  CHECK(without.mode == pa_arena_pole_free);
  CHECK(without.estimate.position_m.z == 3.0);
  CHECK_FALSE(without.catch_predicted);
  CHECK(without.catch_vehicle == 0);

  const gs::dds::CatchForecast forecast{1.6, Eigen::Vector3d(1.0, 0.1, 1.3), pa::kVehicle2};
  const auto with = gs::dds::pole_telemetry_to_dds(pole, 1.0, forecast);
  CHECK(with.catch_predicted);
  CHECK(with.catch_time_ns == 1'600'000'000);
  CHECK(with.catch_point_m.x == 1.0);
  CHECK(with.catch_point_m.z == 1.3);
  CHECK(with.catch_vehicle == 2);
}
