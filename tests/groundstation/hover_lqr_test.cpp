// The hover LQR: its linearisation against the vehicle model's numerical Jacobians, the closed
// loop, and a nonlinear simulation of the model under the gain.
#include "groundstation/control/hover_lqr.hpp"

#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <cmath>

#include "groundstation/model/rk4.hpp"
#include "groundstation/model/vehicle.hpp"

namespace {

namespace hover = gs::control::hover;
using gs::model::VehicleInput;
using gs::model::VehicleState;

Eigen::VectorXd to_vector(const VehicleState& s) {
  Eigen::VectorXd x(hover::kStateSize);
  x << s.p_m, s.v_mps, s.phi_rad, s.theta_rad, s.psi_rad;
  return x;
}
VehicleState from_vector(const Eigen::VectorXd& x) {
  return {x.segment<3>(0), x.segment<3>(3), x(6), x(7), x(8)};
}
VehicleInput input_from(const Eigen::VectorXd& u) {
  VehicleInput in;
  in.a_q_mps2 = u(0);
  in.omega_radps = u.segment<3>(1);
  return in;
}

}  // namespace

TEST_CASE("hover linearisation matches the Jacobians of the vehicle model (4), (5)") {
  const auto analytic = gs::control::hover_linearisation();
  auto f = [](const Eigen::VectorXd& x, const Eigen::VectorXd& u) -> Eigen::VectorXd {
    return to_vector(gs::model::vehicle_dynamics(from_vector(x), input_from(u)));
  };
  Eigen::VectorXd u0(4);
  u0 << pa::kGravity_mps2, 0, 0, 0;
  const auto numeric = gs::control::linearise(f, Eigen::VectorXd::Zero(9), u0);
  CHECK((analytic.A - numeric.A).norm() < 1e-7);
  CHECK((analytic.B - numeric.B).norm() < 1e-7);
}

TEST_CASE("hover LQR: stable closed loop, and the nonlinear vehicle returns to hover") {
  const auto lqr = gs::control::hover_lqr();
  REQUIRE(lqr.ok);
  CHECK(lqr.care_residual < 1e-12);
  CHECK((lqr.closed_loop_eigenvalues.real().array() < 0.0).all());

  // 1 m away, yawed, with 5 ms zero-order hold (the motion-capture rate).
  VehicleState s;
  s.p_m = Eigen::Vector3d(1.0, -0.6, 0.4);
  s.psi_rad = 0.3;
  double thrust_min = 1e9, thrust_max = 0, rate_max = 0;
  const double dt = 1e-3;
  VehicleInput in;
  for (int k = 0; k < 10000; ++k) {
    if (k % 5 == 0) {
      Eigen::VectorXd u = -lqr.K * to_vector(s);
      u(0) += pa::kGravity_mps2;
      in = input_from(u);
      thrust_min = std::min(thrust_min, in.a_q_mps2);
      thrust_max = std::max(thrust_max, in.a_q_mps2);
      rate_max = std::max(rate_max, in.omega_radps.cwiseAbs().maxCoeff());
    }
    s = gs::model::rk4_step([&](const VehicleState& x) { return gs::model::vehicle_dynamics(x, in); }, s, dt);
  }
  CHECK(s.p_m.norm() < 1e-3);
  CHECK(s.v_mps.norm() < 1e-3);
  CHECK(std::abs(s.psi_rad) < 1e-3);
  CHECK(thrust_min >= 1.0);
  CHECK(thrust_max <= 20.0);
  CHECK(rate_max <= 10.0);
}

// The catch must put the plate under the pole's end within its 6 cm radius: from 6 cm off, the
// catch's gain closes the gap to 1 cm sooner than the hover's, within the rate limit.
TEST_CASE("catch LQR: stable, and closes a plate-sized gap sooner than the hover's") {
  const auto time_to_1cm = [](const gs::control::LqrGain& lqr, double& rate_max) {
    VehicleState s;
    s.p_m = Eigen::Vector3d(0.06, 0.0, 0.0);
    const double dt = 1e-3;
    VehicleInput in;
    rate_max = 0.0;
    for (int k = 0; k < 5000; ++k) {
      if (k % 5 == 0) {
        Eigen::VectorXd u = -lqr.K * to_vector(s);
        u(0) += pa::kGravity_mps2;
        in = input_from(u);
        rate_max = std::max(rate_max, in.omega_radps.cwiseAbs().maxCoeff());
      }
      s = gs::model::rk4_step([&](const VehicleState& x) { return gs::model::vehicle_dynamics(x, in); }, s,
                              dt);
      if (std::abs(s.p_m.x()) < 0.01 && std::abs(s.v_mps.x()) < 0.02) return k * dt;
    }
    return 1e9;
  };
  const auto hover = gs::control::hover_lqr();
  const auto catching = gs::control::hover_lqr(gs::control::catch_lqr_weights());
  REQUIRE(catching.ok);
  CHECK((catching.closed_loop_eigenvalues.real().array() < 0.0).all());
  double hover_rate = 0.0, catch_rate = 0.0;
  const double hover_s = time_to_1cm(hover, hover_rate);
  const double catch_s = time_to_1cm(catching, catch_rate);
  INFO("hover " << hover_s << " s, catch " << catch_s << " s");
  CHECK(catch_s < 0.9 * hover_s);
  CHECK(catch_rate <= 10.0);
}
