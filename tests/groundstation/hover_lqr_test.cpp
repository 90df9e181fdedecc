// The hover LQR: its linearisation against the vehicle model's numerical Jacobians, the closed
// loop, and a nonlinear simulation of the model under the gain.
#include "groundstation/control/hover_lqr.hpp"

#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <cmath>
#include <functional>

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

// The vehicle model flown under the gain from `s` for at most `steps` ms, each input held 5 ms
// (the motion capture's period); `done` ends the flight early. The inputs' extremes are kept.
struct Flight {
  VehicleState s;
  double t_s = 0.0;
  bool done = false;
  double thrust_min = 1e9, thrust_max = 0.0, rate_max = 0.0;
};
Flight fly(const gs::control::LqrGain& lqr, const VehicleState& start, int steps,
           const std::function<bool(const VehicleState&)>& done = {}) {
  Flight f;
  f.s = start;
  const double dt = 1e-3;
  VehicleInput in;
  for (int k = 0; k < steps; ++k) {
    if (k % 5 == 0) {
      Eigen::VectorXd u = -lqr.K * to_vector(f.s);
      u(0) += pa::kGravity_mps2;
      in = input_from(u);
      f.thrust_min = std::min(f.thrust_min, in.a_q_mps2);
      f.thrust_max = std::max(f.thrust_max, in.a_q_mps2);
      f.rate_max = std::max(f.rate_max, in.omega_radps.cwiseAbs().maxCoeff());
    }
    f.s = gs::model::rk4_step([&](const VehicleState& x) { return gs::model::vehicle_dynamics(x, in); }, f.s,
                              dt);
    f.t_s = (k + 1) * dt;
    if (done && done(f.s)) {
      f.done = true;
      break;
    }
  }
  return f;
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

  // 1 m away, yawed.
  VehicleState start;
  start.p_m = Eigen::Vector3d(1.0, -0.6, 0.4);
  start.psi_rad = 0.3;
  const Flight f = fly(lqr, start, 10000);
  CHECK(f.s.p_m.norm() < 1e-3);
  CHECK(f.s.v_mps.norm() < 1e-3);
  CHECK(std::abs(f.s.psi_rad) < 1e-3);
  CHECK(f.thrust_min >= 1.0);
  CHECK(f.thrust_max <= 20.0);
  CHECK(f.rate_max <= 10.0);
}

// The catch must put the plate under the pole's end within its 6 cm radius: from 6 cm off, the
// catch's gain closes the gap to 1 cm sooner than the hover's, within the rate limit.
TEST_CASE("catch LQR: stable, and closes a plate-sized gap sooner than the hover's") {
  VehicleState start;
  start.p_m = Eigen::Vector3d(0.06, 0.0, 0.0);
  const auto within_1cm = [](const VehicleState& s) {
    return std::abs(s.p_m.x()) < 0.01 && std::abs(s.v_mps.x()) < 0.02;
  };
  const auto hover = gs::control::hover_lqr();
  const auto catching = gs::control::hover_lqr(gs::control::catch_lqr_weights());
  REQUIRE(catching.ok);
  CHECK((catching.closed_loop_eigenvalues.real().array() < 0.0).all());
  const Flight by_hover = fly(hover, start, 5000, within_1cm);
  const Flight by_catch = fly(catching, start, 5000, within_1cm);
  INFO("hover " << by_hover.t_s << " s, catch " << by_catch.t_s << " s");
  REQUIRE(by_hover.done);
  REQUIRE(by_catch.done);
  CHECK(by_catch.t_s < 0.9 * by_hover.t_s);
  CHECK(by_catch.rate_max <= 10.0);
}
