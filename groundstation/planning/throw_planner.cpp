#include "groundstation/planning/throw_planner.hpp"

#include <IpIpoptApplication.hpp>
#include <IpSolveStatistics.hpp>  // IPOPT 3.11 does not include it from the application header
#include <cmath>
#include <exception>

#include "groundstation/planning/throw_collocation_nlp.hpp"

namespace gs::planning {
namespace {

const char* status_text(Ipopt::ApplicationReturnStatus status) {
  switch (status) {
    case Ipopt::Solve_Succeeded: return "solved";
    case Ipopt::Solved_To_Acceptable_Level: return "solved to acceptable level";
    case Ipopt::Infeasible_Problem_Detected: return "infeasible problem detected";
    case Ipopt::Search_Direction_Becomes_Too_Small: return "search direction became too small";
    case Ipopt::Diverging_Iterates: return "diverging iterates";
    case Ipopt::User_Requested_Stop: return "user requested stop";
    case Ipopt::Feasible_Point_Found: return "feasible point found";
    case Ipopt::Maximum_Iterations_Exceeded: return "maximum iterations exceeded";
    case Ipopt::Restoration_Failed: return "restoration failed";
    case Ipopt::Error_In_Step_Computation: return "error in step computation";
    case Ipopt::Maximum_CpuTime_Exceeded: return "maximum CPU time exceeded";
    case Ipopt::Not_Enough_Degrees_Of_Freedom: return "not enough degrees of freedom";
    case Ipopt::Invalid_Problem_Definition: return "invalid problem definition";
    case Ipopt::Invalid_Option: return "invalid option";
    case Ipopt::Invalid_Number_Detected: return "invalid number detected";
    case Ipopt::Unrecoverable_Exception: return "unrecoverable exception";
    case Ipopt::NonIpopt_Exception_Thrown: return "non-IPOPT exception thrown";
    case Ipopt::Insufficient_Memory: return "insufficient memory";
    case Ipopt::Internal_Error: return "internal error";
  }
  return "unknown IPOPT status";
}

ThrowPlan solve(const ThrowProblem& problem, const ThrowSolverOptions& options,
                const ThrowWarmStart* warm_start) {
  ThrowPlan plan;
  plan.launch_thrust_mps2 = problem.launch_thrust_mps2();
  if (const std::string why = problem.validate(); !why.empty()) {
    plan.status = "rejected: " + why;
    return plan;
  }
  if (options.intervals < 1 || !(options.optimality_tolerance > 0.0) ||
      !(options.feasibility_tolerance > 0.0) || options.max_iterations < 0 ||
      !(options.end_refinement >= 0.0 && options.end_refinement < 1.0)) {
    plan.status = "rejected: invalid solver options";
    return plan;
  }

  Ipopt::SmartPtr<ThrowCollocationNlp> nlp = new ThrowCollocationNlp(
      problem, throw_collocation_mesh(problem.duration_s, options.intervals, options.end_refinement));
  if (warm_start != nullptr) {
    if (warm_start->trajectory.intervals() < 1 ||
        std::abs(warm_start->trajectory.duration_s() - problem.duration_s) > 1e-9) {
      plan.status = "rejected: the warm start does not span the throw's duration";
      return plan;
    }
    nlp->set_warm_start(warm_start->trajectory, warm_start->catch_time_s);
  }
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
  Ipopt::OptionsList& opts = *app->Options();
  opts.SetIntegerValue("print_level", options.print_level);
  opts.SetStringValue("sb", "yes");  // no banner
  opts.SetNumericValue("tol", options.optimality_tolerance);
  opts.SetNumericValue("constr_viol_tol", options.feasibility_tolerance);
  opts.SetIntegerValue("max_iter", options.max_iterations);
  // Adaptive barrier updates from probing (Mehrotra's rule) with an affine corrector step:
  // 9 iterations (10 linear-system factorisations) against 12 with the default quality function
  // and 16 with monotone updates, about 15 % less time than the quality function.
  opts.SetStringValue("mu_strategy", "adaptive");
  opts.SetStringValue("mu_oracle", "probing");
  opts.SetStringValue("corrector_type", "affine");
  // Bound multipliers started from mu rather than at 1: two iterations fewer once the input slew
  // rows bind (mu_init and the other MUMPS orderings gained nothing).
  opts.SetStringValue("bound_mult_init_method", "mu-based");
  // The KKT matrix is well scaled (states and inputs of order 1-10, defects of the same order),
  // and MUMPS's own scaling pass was a seventh of the solve time (same iterations and result).
  opts.SetIntegerValue("mumps_scaling", 0);
  // Nor does it need MUMPS's maximum-transversal permutation: on this KKT structure that pass
  // was most of the symbolic analysis (15 ms of a 100 ms solve), for the same pivots.
  opts.SetIntegerValue("mumps_permuting_scaling", 0);
  // IPOPT still refines a solution whose residual is too large (residual_ratio_max); the one
  // refinement it otherwise always does cost a tenth of the solve here and changed nothing.
  opts.SetIntegerValue("min_refinement_steps", 0);
  opts.SetStringValue("hessian_approximation", options.exact_hessian ? "exact" : "limited-memory");
  // "" skips reading an ipopt.opt from the working directory: results must not depend on it.
  Ipopt::ApplicationReturnStatus status = app->Initialize("");
  if (status == Ipopt::Solve_Succeeded) status = app->OptimizeTNLP(nlp);

  plan.ipopt_status = static_cast<int>(status);
  plan.status = status_text(status);
  if (Ipopt::SmartPtr<Ipopt::SolveStatistics> stats = app->Statistics(); Ipopt::IsValid(stats)) {
    plan.iterations = stats->IterationCount();
  }
  if (nlp->solution().size() != nlp->variable_count()) return plan;

  const Eigen::VectorXd& x = nlp->solution();
  plan.cost = nlp->solution_objective();
  plan.trajectory = nlp->trajectory_from(x);
  plan.max_violation = nlp->max_violation(x);
  if (nlp->has_target()) {
    plan.launch_thrust_mps2 = plan.trajectory.input.back()(model::planar::kThrust);
    plan.catch_time_s = x(nlp->catch_time_variable());
  } else {
    plan.end_state_error = (plan.trajectory.state.back() - problem.launch_state).cwiseAbs().maxCoeff();
  }
  const bool converged = status == Ipopt::Solve_Succeeded || status == Ipopt::Solved_To_Acceptable_Level;
  // The 1e-6 promise of the planner, checked on the returned point rather than trusted.
  plan.success = converged && plan.max_violation <= 1e-6;
  if (converged && !plan.success) plan.status += ", but the result violates a constraint";
  return plan;
}

}  // namespace

ThrowPlan plan_throw(const ThrowProblem& problem, const ThrowSolverOptions& options,
                     const ThrowWarmStart* warm_start) {
  try {
    return solve(problem, options, warm_start);
  } catch (const std::exception& e) {
    ThrowPlan plan;
    plan.status = std::string("solver error: ") + e.what();
    return plan;
  } catch (...) {
    ThrowPlan plan;
    plan.status = "solver error: unknown exception";
    return plan;
  }
}

}  // namespace gs::planning
