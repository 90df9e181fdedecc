// A generic classical Runge-Kutta step for the ground-station models. The state type only needs
// `State + State` and `double * State` (Eigen fixed-size vectors, gs::model::PoleState,
// gs::model::VehicleState, ...); the derivative has the state's type and layout.
#pragma once

namespace gs::model {

// One RK4 step of length dt_s for the autonomous system x' = f(x). The step may be an automatic-
// differentiation scalar (the target throw's catching instant is a variable of the planner).
template <typename State, typename F, typename Time = double>
State rk4_step(F&& f, const State& x, const Time& dt_s) {
  const State k1 = f(x);
  const State k2 = f(State(x + (0.5 * dt_s) * k1));
  const State k3 = f(State(x + (0.5 * dt_s) * k2));
  const State k4 = f(State(x + dt_s * k3));
  // k + k rather than 2.0 * k (the same bits): Eigen defines no double times a vector of nested
  // automatic-differentiation scalars.
  return State(x + (dt_s / 6.0) * State(k1 + (k2 + k2) + (k3 + k3) + k4));
}

}  // namespace gs::model
