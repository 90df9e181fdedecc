// The quadrocopter model, eq. (1)-(8): rotation convention (3), translational dynamics (4) and the
// Euler-rate kinematics (5), checked against rigid-body kinematics integrated independently.
#include "groundstation/model/vehicle.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "groundstation/model/rk4.hpp"

namespace {

using gs::model::VehicleInput;
using gs::model::VehicleState;

constexpr double kG = pa::kGravity_mps2;

Eigen::Matrix3d skew(const Eigen::Vector3d& w) {
  Eigen::Matrix3d s;
  s << 0.0, -w.z(), w.y(), w.z(), 0.0, -w.x(), -w.y(), w.x(), 0.0;
  return s;
}

// exp([w]x) by Rodrigues' formula.
Eigen::Matrix3d exp_skew(const Eigen::Vector3d& w) {
  const double angle = w.norm();
  if (angle < 1e-15) return Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d k = skew(w / angle);
  return Eigen::Matrix3d::Identity() + std::sin(angle) * k + (1.0 - std::cos(angle)) * k * k;
}

}  // namespace

TEST_CASE("eq. (3): B_I R = R_x(phi) R_y(theta) R_z(psi) is a proper rotation", "[vehicle]") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> angle(-1.4, 1.4);
  for (int i = 0; i < 50; ++i) {
    const double phi = angle(rng), theta = angle(rng), psi = 2.0 * angle(rng);
    const Eigen::Matrix3d r = gs::model::rotation_body_from_inertial(phi, theta, psi);
    CHECK((r * r.transpose() - Eigen::Matrix3d::Identity()).norm() < 1e-14);
    CHECK(r.determinant() == Approx(1.0).margin(1e-14));
    CHECK((gs::model::rotation_inertial_from_body(phi, theta, psi) - r.transpose()).norm() < 1e-15);
    CHECK(
        (r - gs::model::rotation_x(phi) * gs::model::rotation_y(theta) * gs::model::rotation_z(psi)).norm() <
        1e-15);
  }
}

TEST_CASE("eq. (3): the passive rotations follow the zyx Euler sequence", "[vehicle]") {
  // Yaw by +90 deg: the body x-axis points along inertial +y.
  const Eigen::Matrix3d yaw = gs::model::rotation_inertial_from_body(0.0, 0.0, M_PI / 2);
  CHECK((yaw * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()).norm() < 1e-15);
  // Pitch theta tilts the thrust axis towards +x: (sin theta, 0, cos theta), the planar model's
  // (sin theta, cos theta).
  const double theta = 0.48;
  const Eigen::Vector3d thrust_pitch =
      gs::model::rotation_inertial_from_body(0.0, theta, 0.0) * Eigen::Vector3d::UnitZ();
  CHECK((thrust_pitch - Eigen::Vector3d(std::sin(theta), 0.0, std::cos(theta))).norm() < 1e-15);
  // Roll phi tilts it towards -y.
  const double phi = 0.3;
  const Eigen::Vector3d thrust_roll =
      gs::model::rotation_inertial_from_body(phi, 0.0, 0.0) * Eigen::Vector3d::UnitZ();
  CHECK((thrust_roll - Eigen::Vector3d(0.0, -std::sin(phi), std::cos(phi))).norm() < 1e-15);
  // Yaw after pitch turns the tilt direction about z.
  const Eigen::Vector3d thrust_yawed =
      gs::model::rotation_inertial_from_body(0.0, theta, M_PI / 2) * Eigen::Vector3d::UnitZ();
  CHECK((thrust_yawed - Eigen::Vector3d(0.0, std::sin(theta), std::cos(theta))).norm() < 1e-15);
}

TEST_CASE("eq. (4): hover, tilted thrust and free fall", "[vehicle]") {
  VehicleState s;
  CHECK(gs::model::vehicle_acceleration_mps2(s, kG).norm() < 1e-15);
  CHECK((gs::model::vehicle_acceleration_mps2(s, 0.0) - Eigen::Vector3d(0, 0, -kG)).norm() < 1e-15);
  s.theta_rad = -0.48;
  const Eigen::Vector3d acc = gs::model::vehicle_acceleration_mps2(s, 4.48);
  CHECK(acc.x() == Approx(4.48 * std::sin(-0.48)));
  CHECK(acc.y() == Approx(0.0).margin(1e-15));
  CHECK(acc.z() == Approx(4.48 * std::cos(-0.48) - kG));
}

TEST_CASE("eq. (5) is the inverse of the printed matrix", "[vehicle]") {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.3, 1.3);
  for (int i = 0; i < 100; ++i) {
    const double phi = u(rng), theta = u(rng);
    const Eigen::Vector3d body(3 * u(rng), 3 * u(rng), 3 * u(rng));
    const Eigen::Vector3d euler = gs::model::euler_rates_from_body_rates(phi, theta, body);
    CHECK((gs::model::body_rates_from_euler_rates(phi, theta, euler) - body).norm() < 1e-12);
  }
  // In the plane (phi = 0) the pitch rate is Omega_y, as the planar model assumes.
  const Eigen::Vector3d planar = gs::model::euler_rates_from_body_rates(0.0, -0.48, {0.0, 2.5, 0.0});
  CHECK(planar.x() == Approx(0.0).margin(1e-15));
  CHECK(planar.y() == Approx(2.5));
  CHECK(planar.z() == Approx(0.0).margin(1e-15));
}

TEST_CASE("eq. (5): integrated Euler rates reproduce the body-rate rotation", "[vehicle]") {
  // A constant body rate turns the attitude as ^I_B R(t) = ^I_B R(0) exp([Omega]x t). Integrating
  // f_q's Euler rates must give the same rotation matrix; the printed (uninverted) matrix would
  // not.
  VehicleState s;
  s.phi_rad = 0.2;
  s.theta_rad = -0.3;
  s.psi_rad = 0.5;
  VehicleInput input;
  input.omega_radps = Eigen::Vector3d(0.7, -0.4, 0.9);
  const Eigen::Matrix3d r0 = gs::model::rotation_inertial_from_body(s.phi_rad, s.theta_rad, s.psi_rad);
  const double duration = 1.0;
  const double dt = 1e-3;
  for (int i = 0; i < static_cast<int>(duration / dt); ++i) {
    s = gs::model::rk4_step([&](const VehicleState& x) { return gs::model::vehicle_dynamics(x, input); }, s,
                            dt);
  }
  const Eigen::Matrix3d expected = r0 * exp_skew(input.omega_radps * duration);
  const Eigen::Matrix3d integrated =
      gs::model::rotation_inertial_from_body(s.phi_rad, s.theta_rad, s.psi_rad);
  CHECK((integrated - expected).norm() < 1e-9);
}

TEST_CASE("eq. (8): constant attitude and thrust give uniform acceleration", "[vehicle]") {
  VehicleState s;
  s.theta_rad = 0.2;
  s.v_mps = Eigen::Vector3d(0.3, -0.1, 1.0);
  const VehicleState s0 = s;
  VehicleInput input;
  input.a_q_mps2 = 12.0;
  const Eigen::Vector3d acc = gs::model::vehicle_acceleration_mps2(s0, input.a_q_mps2);
  const double dt = 0.01;
  for (int i = 0; i < 150; ++i) {
    s = gs::model::rk4_step([&](const VehicleState& x) { return gs::model::vehicle_dynamics(x, input); }, s,
                            dt);
  }
  const double t = 1.5;
  CHECK((s.p_m - (s0.p_m + s0.v_mps * t + 0.5 * acc * t * t)).norm() < 1e-12);
  CHECK((s.v_mps - (s0.v_mps + acc * t)).norm() < 1e-12);
  CHECK(s.theta_rad == Approx(s0.theta_rad));
}
