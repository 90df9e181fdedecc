// Solves the throw problem (34) (Section III-A) by Hermite-Simpson direct collocation
// (throw_collocation_nlp.hpp) with IPOPT, from the straight line between hover and the launch
// state, with exact sparse first and second derivatives.
#pragma once

#include <string>

#include "groundstation/planning/throw_problem.hpp"
#include "groundstation/planning/throw_trajectory.hpp"

namespace gs::planning {

struct ThrowSolverOptions {
  int intervals = 100;          // N, collocation intervals over [0, T]
  double end_refinement = 0.9;  // mesh grading, see throw_collocation_mesh
  // IPOPT's tol (the overall optimality error) and constr_viol_tol (absolute, the unscaled
  // problem); the result is held against 1e-6 on every constraint.
  double optimality_tolerance = 1e-8;
  double feasibility_tolerance = 1e-9;
  int max_iterations = 300;
  int print_level = 0;        // IPOPT's 0..12
  bool exact_hessian = true;  // false: hessian_approximation limited-memory
};

struct ThrowPlan {
  bool success = false;  // IPOPT converged and the result meets every constraint
  int ipopt_status = 0;  // Ipopt::ApplicationReturnStatus
  std::string status;    // readable solver status, or why the problem was rejected
  double cost = 0.0;     // J of (34)
  int iterations = 0;
  double max_violation = 0.0;       // worst constraint or bound violation of the result
  double end_state_error = 0.0;     // max |s(T) - s_T| over the state components (fixed end)
  double launch_thrust_mps2 = 0.0;  // a_q,T from F_N = 0
  double catch_time_s = 0.0;        // target throws: the catching instant t_c after the release
  ThrowTrajectory trajectory;       // empty unless IPOPT returned a point
};

// A starting point for the solver: a trajectory over the same duration (any mesh) and, for a
// target throw, its catching instant.
struct ThrowWarmStart {
  ThrowTrajectory trajectory;
  double catch_time_s = 0.0;
};

// Never throws; a rejected problem or a solver failure comes back with success = false. Without
// a warm start the solver starts from the straight line between hover and problem.launch_state.
ThrowPlan plan_throw(const ThrowProblem& problem, const ThrowSolverOptions& options = {},
                     const ThrowWarmStart* warm_start = nullptr);

}  // namespace gs::planning
