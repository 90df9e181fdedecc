// The balancing LQR: the numerical linearisation of the pole-on-vehicle model (30) against the
// hand derivation and the planar model, the closed loop, and nonlinear simulations (planar and
// 3D) from a tilted pole and an offset vehicle.
#include "groundstation/control/balancing_lqr.hpp"

#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <cmath>

#include "groundstation/control/linear_system.hpp"
#include "groundstation/model/planar_pole_vehicle.hpp"
#include "groundstation/model/rk4.hpp"

namespace {

namespace bal = gs::control::balancing;
constexpr double kG = pa::kGravity_mps2;
constexpr double kL = pa::kPoleHalfLength_m;

// The hand derivation (header comment of balancing_lqr.hpp): hover plus
//   a'' = (3g/4L) a - (3g/4) theta,  b'' = (3g/4L) b + (3g/4) phi.
gs::control::LinearSystem analytic_linearisation() {
  gs::control::LinearSystem s{Eigen::MatrixXd::Zero(13, 13), Eigen::MatrixXd::Zero(13, 4)};
  s.A(bal::kX, bal::kVx) = s.A(bal::kY, bal::kVy) = s.A(bal::kZ, bal::kVz) = 1.0;
  s.A(bal::kVx, bal::kPitch) = kG;
  s.A(bal::kVy, bal::kRoll) = -kG;
  s.A(bal::kA, bal::kADot) = s.A(bal::kB, bal::kBDot) = 1.0;
  s.A(bal::kADot, bal::kA) = s.A(bal::kBDot, bal::kB) = 3.0 * kG / (4.0 * kL);
  s.A(bal::kADot, bal::kPitch) = -0.75 * kG;
  s.A(bal::kBDot, bal::kRoll) = 0.75 * kG;
  s.B(bal::kVz, bal::kThrust) = 1.0;
  s.B(bal::kRoll, bal::kRateX) = s.B(bal::kPitch, bal::kRateY) = s.B(bal::kYaw, bal::kRateZ) = 1.0;
  return s;
}

}  // namespace

TEST_CASE("balancing linearisation: the model's Jacobians match the hand derivation") {
  const auto numeric = gs::control::balancing_linearisation();
  const auto analytic = analytic_linearisation();
  CHECK((numeric.A - analytic.A).cwiseAbs().maxCoeff() < 1e-6);
  CHECK((numeric.B - analytic.B).cwiseAbs().maxCoeff() < 1e-6);
}

TEST_CASE("balancing linearisation: the planar model agrees in its plane") {
  // Planar state (x, z, vx, vz, theta, alpha, alpha'); a = L sin(alpha), so at the upright
  // a = L alpha and a' = L alpha' to first order.
  namespace pl = gs::model::planar;
  auto f = [](const Eigen::VectorXd& x, const Eigen::VectorXd& u) -> Eigen::VectorXd {
    return gs::model::planar_pole_vehicle_dynamics<double>(x, u);
  };
  Eigen::VectorXd u0(2);
  u0 << kG, 0.0;
  const auto planar = gs::control::linearise(f, Eigen::VectorXd::Zero(7), u0);
  const auto full = gs::control::balancing_linearisation();
  // Planar index -> 13-state index, and the scale from alpha to a.
  const int map[7] = {bal::kX, bal::kZ, bal::kVx, bal::kVz, bal::kPitch, bal::kA, bal::kADot};
  const double scale[7] = {1, 1, 1, 1, 1, kL, kL};
  for (int i = 0; i < 7; ++i) {
    for (int j = 0; j < 7; ++j) {
      CAPTURE(i, j);
      CHECK(full.A(map[i], map[j]) == Approx(scale[i] / scale[j] * planar.A(i, j)).margin(1e-6));
    }
    CHECK(full.B(map[i], bal::kThrust) == Approx(scale[i] * planar.B(i, pl::kThrust)).margin(1e-6));
    CHECK(full.B(map[i], bal::kRateY) == Approx(scale[i] * planar.B(i, pl::kPitchRate)).margin(1e-6));
  }
}

TEST_CASE("balancing LQR: the closed loop is stable") {
  const auto lqr = gs::control::balancing_lqr();
  REQUIRE(lqr.ok);
  CHECK(lqr.care_residual < 1e-12);
  const Eigen::VectorXd re = lqr.closed_loop_eigenvalues.real();
  INFO("closed-loop eigenvalues (real parts): " << re.transpose());
  CHECK(re.maxCoeff() < 0.0);
  // The open loop is unstable (the inverted pendulum, sqrt(3g/4L) = 3.3 1/s).
  const auto open = gs::control::balancing_linearisation();
  CHECK(open.A.eigenvalues().real().maxCoeff() == Approx(std::sqrt(3.0 * kG / (4.0 * kL))).epsilon(1e-6));
}

TEST_CASE("balancing LQR: the nonlinear planar pole on a vehicle returns upright to the origin") {
  namespace pl = gs::model::planar;
  const auto lqr = gs::control::balancing_lqr();
  REQUIRE(lqr.ok);
  gs::model::PlanarState<double> s = gs::model::PlanarState<double>::Zero();
  s(pl::kAlpha) = 5.0 * M_PI / 180.0;
  s(pl::kX) = 0.2;
  gs::model::PlanarInput<double> u = gs::model::PlanarInput<double>::Zero();
  double thrust_min = 1e9, thrust_max = 0.0, rate_max = 0.0, alpha_max = 0.0;
  const double dt = 1e-3;
  for (int k = 0; k < 10000; ++k) {
    if (k % 5 == 0) {  // 200 Hz zero-order hold
      Eigen::VectorXd x = Eigen::VectorXd::Zero(bal::kStateSize);
      x(bal::kX) = s(pl::kX);
      x(bal::kZ) = s(pl::kZ);
      x(bal::kVx) = s(pl::kVx);
      x(bal::kVz) = s(pl::kVz);
      x(bal::kPitch) = s(pl::kTheta);
      x(bal::kA) = kL * std::sin(s(pl::kAlpha));
      x(bal::kADot) = kL * std::cos(s(pl::kAlpha)) * s(pl::kAlphaDot);
      const Eigen::VectorXd du = -lqr.K * x;
      u(pl::kThrust) = kG + du(bal::kThrust);
      u(pl::kPitchRate) = du(bal::kRateY);
      // Nothing leaks into the other axes from a planar state.
      REQUIRE(std::abs(du(bal::kRateX)) < 1e-12);
      REQUIRE(std::abs(du(bal::kRateZ)) < 1e-12);
      thrust_min = std::min(thrust_min, u(pl::kThrust));
      thrust_max = std::max(thrust_max, u(pl::kThrust));
      rate_max = std::max(rate_max, std::abs(u(pl::kPitchRate)));
    }
    s = gs::model::rk4_step(
        [&](const gs::model::PlanarState<double>& x) {
          return gs::model::PlanarState<double>(gs::model::planar_pole_vehicle_dynamics<double>(x, u));
        },
        s, dt);
    alpha_max = std::max(alpha_max, std::abs(s(pl::kAlpha)));
  }
  INFO("thrust in [" << thrust_min << ", " << thrust_max << "] m/s^2, |Omega_y| <= " << rate_max
                     << " rad/s, |alpha| <= " << alpha_max * 180 / M_PI << " deg");
  CHECK(std::abs(s(pl::kAlpha)) < 0.1 * M_PI / 180.0);
  CHECK(std::abs(s(pl::kAlphaDot)) < 1e-3);
  CHECK(std::abs(s(pl::kX)) < 5e-3);
  CHECK(std::abs(s(pl::kZ)) < 5e-3);
  CHECK(std::abs(s(pl::kTheta)) < 1e-3);
  CHECK(thrust_min >= 1.0);
  CHECK(thrust_max <= 20.0);
  CHECK(rate_max <= 10.0);
  CHECK(alpha_max < 0.5);  // never close to falling
}

TEST_CASE("balancing LQR: the 3D pole-on-vehicle model returns upright from a skew tilt") {
  const auto lqr = gs::control::balancing_lqr();
  REQUIRE(lqr.ok);
  gs::model::VehiclePoleState s;
  s.vehicle.p_m = Eigen::Vector3d(0.2, -0.15, 0.1);
  s.vehicle.psi_rad = 0.2;
  s.pole.a_m = kL * std::sin(4.0 * M_PI / 180.0);
  s.pole.b_m = -kL * std::sin(3.0 * M_PI / 180.0);
  const gs::model::PoleParams params;
  gs::model::VehicleInput in;
  double thrust_min = 1e9, thrust_max = 0.0, rate_max = 0.0;
  for (int k = 0; k < 10000; ++k) {
    if (k % 5 == 0) {
      Eigen::VectorXd u = -lqr.K * gs::control::to_balancing_vector(s);
      u(bal::kThrust) += kG;
      in = gs::control::from_balancing_input(u);
      thrust_min = std::min(thrust_min, in.a_q_mps2);
      thrust_max = std::max(thrust_max, in.a_q_mps2);
      rate_max = std::max(rate_max, in.omega_radps.cwiseAbs().maxCoeff());
    }
    s = gs::model::rk4_step(
        [&](const gs::model::VehiclePoleState& x) { return gs::model::vehicle_pole_dynamics(x, in, params); },
        s, 1e-3);
  }
  CHECK(gs::control::to_balancing_vector(s).norm() < 1e-2);
  CHECK(std::hypot(s.pole.a_m, s.pole.b_m) < 1e-3);
  CHECK(thrust_min >= 1.0);
  CHECK(thrust_max <= 20.0);
  CHECK(rate_max <= 10.0);
}
