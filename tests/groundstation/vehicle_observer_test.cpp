// The vehicle observer (estimation/vehicle_observer.hpp) against the truth world's vehicles:
// the Euler-angle convention of eq. (3), tracking with and without the commanded inputs,
// consistency of its innovations, outliers, dropouts, and the plate kinematics.
#include "groundstation/estimation/vehicle_observer.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <random>

#include "estimation_test_feed.hpp"
#include "fw/config.hpp"

namespace {

using estimation_test::World;
using estimation_test::WorldParams;
using gs::estimation::MocapPose;
using gs::estimation::VehicleObserver;
using estimation_test::to_input;
using estimation_test::to_pose;

struct TrackingStats {
  double position_rms_m = 0.0;
  double velocity_rms_mps = 0.0;
  double acceleration_rms_mps2 = 0.0;
  double attitude_rms_rad = 0.0;
  double mean_nis = 0.0;
  int samples = 0;
};

// Flies vehicle 0 of a world through a sequence of position targets (steps, so the controller
// commands large accelerations and rates) and runs the observer on its poses.
TrackingStats track(bool commanded, unsigned seed, double duration_s = 6.0) {
  World w(WorldParams{}, seed);
  w.vehicle(0).p = Eigen::Vector3d(0.0, 0.0, 1.0);
  w.vehicle(1).p = Eigen::Vector3d(3.0, 0.0, 1.0);
  w.place_pole_free(Eigen::Vector3d(0.0, 5.0, 10.0), Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(),
                    Eigen::Vector3d::Zero());
  VehicleObserver obs(estimation_test::observer_for());
  TrackingStats s;
  double nis_sum = 0.0;
  int nis_count = 0;
  const int steps = w.params().steps_per_frame;
  const int frames = static_cast<int>(duration_s / 0.005);
  for (int k = 0; k < frames; ++k) {
    const double t = w.time();
    const Eigen::Vector3d target(t > 1.0 ? 1.0 : 0.0, t > 2.5 ? -0.5 : 0.0, t > 4.0 ? 1.6 : 1.0);
    World::Vehicle& v = w.vehicle(0);
    v.cmd = estimation_test::hold_position(w, v, target);
    w.vehicle(1).cmd = estimation_test::hold_position(w, w.vehicle(1), Eigen::Vector3d(3, 0, 1));
    const estimation_test::Frame f = w.frame();
    const gs::estimation::VehicleUpdateResult r = obs.update(to_pose(f.vehicle[0]));
    if (k > 0 && r.accepted) {
      nis_sum += r.nis;
      ++nis_count;
    }
    if (t > 0.5) {
      const gs::estimation::VehicleEstimate e = obs.estimate();
      const Eigen::Vector3d acc_true = w.vehicle_acceleration(v);
      s.position_rms_m += (e.state.p_m - v.p).squaredNorm();
      s.velocity_rms_mps += (e.state.v_mps - v.v).squaredNorm();
      s.acceleration_rms_mps2 += (e.acceleration_mps2 - acc_true).squaredNorm();
      const Eigen::Matrix3d r_est =
          gs::model::rotation_inertial_from_body(e.state.phi_rad, e.state.theta_rad, e.state.psi_rad);
      s.attitude_rms_rad += std::pow(Eigen::AngleAxisd(r_est.transpose() * v.r).angle(), 2);
      ++s.samples;
    }
    const gs::model::VehicleInput in = to_input(v.cmd);
    for (int i = 0; i < steps; ++i) w.step();
    obs.predict(0.005, commanded ? &in : nullptr);
  }
  const double n = s.samples;
  s.position_rms_m = std::sqrt(s.position_rms_m / n);
  s.velocity_rms_mps = std::sqrt(s.velocity_rms_mps / n);
  s.acceleration_rms_mps2 = std::sqrt(s.acceleration_rms_mps2 / n);
  s.attitude_rms_rad = std::sqrt(s.attitude_rms_rad / n);
  s.mean_nis = nis_sum / nis_count;
  return s;
}

}  // namespace

TEST_CASE("Euler angles from a pose follow eq. (3)", "[estimation]") {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 200; ++i) {
    const double phi = 3.0 * u(rng);
    const double theta = 1.5 * u(rng);
    const double psi = 3.1 * u(rng);
    const Eigen::Matrix3d r = gs::model::rotation_inertial_from_body(phi, theta, psi);
    const gs::estimation::EulerZyx e = gs::estimation::euler_zyx_from_quaternion(Eigen::Quaterniond(r));
    CHECK(e.phi_rad == Approx(phi).margin(1e-9));
    CHECK(e.theta_rad == Approx(theta).margin(1e-9));
    CHECK(e.psi_rad == Approx(psi).margin(1e-9));
  }
  // Pitch tilts the thrust axis towards +x (the planar model's (sin theta, cos theta)).
  const Eigen::Quaterniond q(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()));
  CHECK(gs::estimation::euler_zyx_from_quaternion(q).theta_rad == Approx(0.3));
  CHECK((q * Eigen::Vector3d::UnitZ()).x() == Approx(std::sin(0.3)));
  CHECK(gs::estimation::wrap_angle_rad(3.5) == Approx(3.5 - 2.0 * M_PI));
  CHECK(gs::estimation::wrap_angle_rad(-3.5) == Approx(2.0 * M_PI - 3.5));
}

TEST_CASE("the observer driven by the commands tracks a manoeuvring vehicle", "[estimation]") {
  const TrackingStats s = track(true, 11);
  std::printf("vehicle observer, commanded: position %.2f mm, velocity %.1f mm/s, acceleration "
              "%.2f m/s^2, attitude %.2f mrad RMS; mean NIS %.2f (6 dof)\n",
              1e3 * s.position_rms_m, 1e3 * s.velocity_rms_mps, s.acceleration_rms_mps2,
              1e3 * s.attitude_rms_rad, s.mean_nis);
  // The noise is 1 mm / 1 mrad per axis, i.e. 1.7 mm / 1.7 mrad as a 3D error.
  CHECK(s.position_rms_m < 1e-3);
  CHECK(s.velocity_rms_mps < 0.03);
  CHECK(s.acceleration_rms_mps2 < 0.4);
  CHECK(s.attitude_rms_rad < 1.5e-3);
  CHECK(s.mean_nis > 3.0);
  CHECK(s.mean_nis < 9.0);
}

TEST_CASE("without commands the observer still tracks, less tightly", "[estimation]") {
  const TrackingStats cmd = track(true, 12);
  const TrackingStats free = track(false, 12);
  std::printf("vehicle observer, no commands: position %.2f mm, velocity %.1f mm/s, acceleration "
              "%.2f m/s^2 RMS; mean NIS %.2f\n",
              1e3 * free.position_rms_m, 1e3 * free.velocity_rms_mps, free.acceleration_rms_mps2,
              free.mean_nis);
  CHECK(free.position_rms_m < 1.5e-3);
  CHECK(free.velocity_rms_mps < 0.08);
  CHECK(free.acceleration_rms_mps2 < 2.0);
  CHECK(free.acceleration_rms_mps2 > cmd.acceleration_rms_mps2);  // the commands are information
}

TEST_CASE("a glitch is rejected, a real jump re-initialises", "[estimation]") {
  VehicleObserver obs(estimation_test::observer_for());
  MocapPose pose;
  pose.p_m = Eigen::Vector3d(1.0, 2.0, 1.5);
  obs.reset(pose);
  gs::model::VehicleInput hover;
  for (int k = 0; k < 40; ++k) {
    obs.predict(0.005, &hover);
    obs.update(pose);
  }
  MocapPose glitch = pose;
  glitch.p_m.x() += 0.5;
  obs.predict(0.005, &hover);
  const auto r = obs.update(glitch);
  CHECK_FALSE(r.accepted);
  CHECK(obs.estimate().state.p_m.x() == Approx(1.0).margin(1e-3));
  // The same jump, persisting: after max_rejections the observer starts over there.
  bool reinitialised = false;
  for (int k = 0; k < 10 && !reinitialised; ++k) {
    obs.predict(0.005, &hover);
    reinitialised = obs.update(glitch).reinitialised;
  }
  CHECK(reinitialised);
  CHECK(obs.estimate().state.p_m.x() == Approx(1.5).margin(1e-3));
  // Non-finite poses are ignored.
  MocapPose bad = pose;
  bad.p_m.y() = std::nan("");
  CHECK_FALSE(obs.update(bad).accepted);
  bad = pose;
  bad.q = Eigen::Quaterniond(0.0, 0.0, 0.0, 0.0);
  CHECK_FALSE(obs.update(bad).accepted);
}

TEST_CASE("a dropout is coasted through on the model, the covariance growing", "[estimation]") {
  World w(WorldParams{}, 5);
  w.vehicle(0).p = Eigen::Vector3d(0.0, 0.0, 1.0);
  w.place_pole_free(Eigen::Vector3d(0.0, 5.0, 10.0), Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(),
                    Eigen::Vector3d::Zero());
  VehicleObserver obs(estimation_test::observer_for());
  double sigma_before = 0.0;
  double error_after = 0.0;
  double sigma_after = 0.0;
  for (int k = 0; k < 400; ++k) {
    World::Vehicle& v = w.vehicle(0);
    v.cmd = estimation_test::hold_position(w, v, Eigen::Vector3d(k > 200 ? 0.8 : 0.0, 0.0, 1.0));
    const estimation_test::Frame f = w.frame();
    const bool dropped = k >= 210 && k < 230;  // 100 ms without poses, while accelerating
    if (k == 210) sigma_before = obs.estimate().position_sigma_m.x();
    if (!dropped) {
      if (k == 230) {
        error_after = (obs.estimate().state.p_m - v.p).norm();
        sigma_after = obs.estimate().position_sigma_m.x();
      }
      obs.update(to_pose(f.vehicle[0]));
    }
    const gs::model::VehicleInput in = to_input(v.cmd);
    for (int i = 0; i < w.params().steps_per_frame; ++i) w.step();
    obs.predict(0.005, &in);
  }
  std::printf("vehicle observer, 100 ms dropout while accelerating: error %.2f mm at its end, "
              "position sigma %.2f -> %.2f mm\n",
              1e3 * error_after, 1e3 * sigma_before, 1e3 * sigma_after);
  CHECK(error_after < 0.01);
  CHECK(sigma_after > 3.0 * sigma_before);
  CHECK(error_after < 4.0 * sigma_after);
}

TEST_CASE("the plate is h above the centre of gravity along the thrust axis", "[estimation]") {
  VehicleObserver obs(estimation_test::observer_for());
  MocapPose pose;
  pose.p_m = Eigen::Vector3d(0.5, 0.0, 1.0);
  pose.q = Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitY()));
  obs.reset(pose);
  const gs::estimation::PlateKinematics plate = obs.plate();
  const double h = pa::kPlateHeightAboveCg_m;
  CHECK(plate.p_m.x() == Approx(0.5 + h * std::sin(0.4)));
  CHECK(plate.p_m.z() == Approx(1.0 + h * std::cos(0.4)));
  CHECK(plate.normal().isApprox(pose.q * Eigen::Vector3d::UnitZ()));
}

TEST_CASE("the rate loop's response is second order, with the firmware's gains", "[estimation]") {
  VehicleObserver obs;
  const gs::estimation::VehicleObserverParams& params = obs.params();
  // The model's constants follow from the firmware's rate gains and motor lag (the header).
  const fw::VehicleConfig firmware;
  for (int i = 0; i < 3; ++i) {
    const double kp = firmware.rate.kp_per_s[i];
    const double tau = firmware.airframe.motor_time_constant_s;
    CHECK(params.rate_natural_frequency_radps(i) == Approx(std::sqrt(kp / tau)).epsilon(0.01));
    CHECK(params.rate_damping(i) == Approx(1.0 / (2.0 * std::sqrt(kp * tau))).epsilon(0.02));
  }
  MocapPose pose;
  pose.p_m = Eigen::Vector3d(0.0, 0.0, 1.0);
  obs.reset(pose);
  gs::model::VehicleInput step;
  step.a_q_mps2 = 9.81;
  step.omega_radps = Eigen::Vector3d(0.0, 3.0, 0.0);
  // Omega' is continuous at the step (a first-order lag would jump to 3 / tau = 200 rad/s^2).
  obs.predict(0.001, &step);
  CHECK(std::abs(obs.estimate().body_rate_derivative_radps2.y()) < 5.0);
  // Then it rises, overshoots by exp(-pi zeta / sqrt(1 - zeta^2)) and settles on the command.
  double peak = 0.0;
  for (int k = 0; k < 300; ++k) {
    obs.predict(0.001, &step);
    peak = std::max(peak, obs.estimate().body_rates_radps.y());
  }
  const double zeta = params.rate_damping.y();
  CHECK(peak == Approx(3.0 * (1.0 + std::exp(-M_PI * zeta / std::sqrt(1.0 - zeta * zeta)))).epsilon(0.01));
  CHECK(obs.estimate().body_rates_radps.y() == Approx(3.0).epsilon(0.01));
}
