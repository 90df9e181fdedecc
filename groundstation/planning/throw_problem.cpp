#include "groundstation/planning/throw_problem.hpp"

#include <cmath>

namespace gs::planning {

namespace planar = model::planar;

model::PlanarState<double> ThrowProblem::figure5_launch_state() {
  model::PlanarState<double> s;
  s(planar::kX) = 1.5;
  s(planar::kZ) = 2.0;
  s(planar::kVx) = 0.3;
  s(planar::kVz) = 5.5;
  s(planar::kTheta) = -0.48;
  s(planar::kAlpha) = 0.48;
  s(planar::kAlphaDot) = 2.5;
  return s;
}

model::VehicleLimits ThrowProblem::default_limits() {
  model::VehicleLimits limits;
  limits.a_q_min_mps2 = 1.0;
  limits.a_q_max_mps2 = 20.0;
  limits.omega_max_radps = 10.0;
  return limits;
}

double ThrowProblem::launch_thrust_mps2() const {
  return model::planar_launch_thrust_mps2(launch_state(planar::kTheta), launch_state(planar::kAlpha),
                                          launch_state(planar::kAlphaDot), params);
}

model::PlanarInput<double> ThrowProblem::launch_input() const {
  return model::PlanarInput<double>(launch_thrust_mps2(), launch_pitch_rate_radps);
}

model::PlanarInput<double> ThrowProblem::hover_input() const {
  return model::PlanarInput<double>(params.gravity_mps2, 0.0);
}

std::string ThrowProblem::validate() const {
  if (!(duration_s > 0.0) || !std::isfinite(duration_s)) return "duration must be positive";
  if (!launch_state.allFinite() || !std::isfinite(launch_pitch_rate_radps)) {
    return "launch state is not finite";
  }
  if (!(limits.a_q_min_mps2 > 0.0) || !(limits.a_q_max_mps2 > limits.a_q_min_mps2) ||
      !(limits.omega_max_radps > 0.0)) {
    return "input limits violate eq. (1)/(2)";
  }
  if (!(thrust_rate_max_mps3 >= 0.0) || !(pitch_acceleration_max_radps2 >= 0.0)) {
    return "input slew limits must be >= 0 (0: none)";
  }
  const auto in_box = [&](const model::PlanarInput<double>& u) {
    return u(planar::kThrust) >= limits.a_q_min_mps2 && u(planar::kThrust) <= limits.a_q_max_mps2 &&
           std::abs(u(planar::kPitchRate)) <= limits.omega_max_radps;
  };
  if (!in_box(hover_input())) return "the hover input (g, 0) is outside the input limits";
  if (catch_target) {
    const ThrowCatchTarget& t = *catch_target;
    if (!std::isfinite(t.distance_m) || !std::isfinite(t.height_m) || !std::isfinite(t.base_offset_rad) ||
        !(t.catch_time_guess_s > 0.0) || t.flight_steps < 1 || !(t.min_catch_time_s >= 0.0) ||
        !(t.min_catch_time_s < 3.0)) {
      return "the catch target is not finite, its catching-instant guess or flight steps not positive, or its "
             "shortest flight outside [0, 3) s";
    }
    return {};  // the launch input is a variable, kept in the box by the planner
  }
  if (!in_box(launch_input())) {
    return "the launch input (a_q,T = " + std::to_string(launch_thrust_mps2()) +
           " m/s^2 from F_N = 0, Omega_T) is outside the input limits";
  }
  return {};
}

}  // namespace gs::planning
