#include "groundstation/control/balancing_lqr.hpp"

namespace gs::control {

Eigen::VectorXd to_balancing_vector(const model::VehiclePoleState& s) {
  Eigen::VectorXd x(balancing::kStateSize);
  x << s.vehicle.p_m, s.vehicle.v_mps, s.vehicle.phi_rad, s.vehicle.theta_rad, s.vehicle.psi_rad, s.pole.a_m,
      s.pole.b_m, s.pole.a_dot_mps, s.pole.b_dot_mps;
  return x;
}

model::VehiclePoleState from_balancing_vector(const Eigen::VectorXd& x) {
  using namespace balancing;
  model::VehiclePoleState s;
  s.vehicle.p_m = x.segment<3>(kX);
  s.vehicle.v_mps = x.segment<3>(kVx);
  s.vehicle.phi_rad = x(kRoll);
  s.vehicle.theta_rad = x(kPitch);
  s.vehicle.psi_rad = x(kYaw);
  s.pole.a_m = x(kA);
  s.pole.b_m = x(kB);
  s.pole.a_dot_mps = x(kADot);
  s.pole.b_dot_mps = x(kBDot);
  return s;
}

Eigen::VectorXd to_balancing_input(const model::VehicleInput& input) {
  Eigen::VectorXd u(balancing::kInputSize);
  u << input.a_q_mps2, input.omega_radps;
  return u;
}

model::VehicleInput from_balancing_input(const Eigen::VectorXd& u) {
  model::VehicleInput input;
  input.a_q_mps2 = u(balancing::kThrust);
  input.omega_radps = u.segment<3>(balancing::kRateX);
  return input;
}

LinearSystem balancing_linearisation(const model::PoleParams& params) {
  const Eigen::VectorXd x0 = Eigen::VectorXd::Zero(balancing::kStateSize);
  model::VehicleInput hover;
  hover.a_q_mps2 = params.gravity_mps2;
  const Eigen::VectorXd u0 = to_balancing_input(hover);
  auto f = [&params](const Eigen::VectorXd& x, const Eigen::VectorXd& u) -> Eigen::VectorXd {
    return to_balancing_vector(
        model::vehicle_pole_dynamics(from_balancing_vector(x), from_balancing_input(u), params));
  };
  return linearise(f, x0, u0);
}

LqrWeights balancing_lqr_weights() {
  LqrWeights w;
  w.state =
      (Eigen::VectorXd(balancing::kStateSize) << 2, 2, 4, 1, 1, 1, 0.5, 0.5, 0.5, 20, 20, 2, 2).finished();
  w.input = (Eigen::VectorXd(balancing::kInputSize) << 0.5, 0.5, 0.5, 0.5).finished();
  return w;
}

LqrGain balancing_lqr(const LqrWeights& weights, const model::PoleParams& params) {
  return solve_lqr(balancing_linearisation(params), weights);
}

}  // namespace gs::control
