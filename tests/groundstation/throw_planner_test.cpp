// The optimal throw (problem (34), Section III-A): the collocation NLP's derivatives, the solved
// trajectory against every constraint, and the trajectory flown open loop on the planar model.
#include "groundstation/planning/throw_planner.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>

#include "groundstation/planning/throw_collocation_nlp.hpp"
#include "throw_plan_checks.hpp"

namespace {

using gs::model::PlanarInput;
using gs::model::PlanarState;
using gs::planning::ThrowCollocationNlp;
using gs::planning::ThrowPlan;
using gs::planning::ThrowProblem;
using gs::planning::ThrowTrajectory;
namespace planar = gs::model::planar;

const ThrowPlan& paper_plan() {
  static const ThrowPlan plan = gs::planning::plan_throw(ThrowProblem{});
  return plan;
}

// Simpson quadrature of (34)'s integrand with the paper's weights over the collocation points.
double paper_cost(const ThrowTrajectory& traj) {
  const auto l = [&](int j) {
    const double alpha = traj.state[j](planar::kAlpha);
    const double da = traj.input[j](planar::kThrust) - pa::kGravity_mps2;
    const double om = traj.input[j](planar::kPitchRate);
    return 1.5 * alpha * alpha + da * da + 8.0 * om * om;
  };
  double cost = 0.0;
  for (int k = 0; k < traj.intervals(); ++k) {
    cost += (traj.t_s[2 * k + 2] - traj.t_s[2 * k]) / 6.0 * (l(2 * k) + 4.0 * l(2 * k + 1) + l(2 * k + 2));
  }
  return cost;
}

PlanarState<double> rk4_step(const PlanarState<double>& s, double t, double h, const ThrowTrajectory& traj) {
  const auto f = [&](const PlanarState<double>& x, double tt) -> PlanarState<double> {
    return gs::model::planar_pole_vehicle_dynamics<double>(x, traj.input_at(tt), traj.params);
  };
  const PlanarState<double> k1 = f(s, t);
  const PlanarState<double> k2 = f(s + 0.5 * h * k1, t + 0.5 * h);
  const PlanarState<double> k3 = f(s + 0.5 * h * k2, t + 0.5 * h);
  const PlanarState<double> k4 = f(s + h * k3, t + h);
  return s + (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
}

}  // namespace

TEST_CASE("the collocation mesh is graded towards both ends", "[throw_planner]") {
  const std::vector<double> knots = gs::planning::throw_collocation_mesh(2.5, 100, 0.9);
  REQUIRE(knots.size() == 101);
  CHECK(knots.front() == 0.0);
  CHECK(knots.back() == 2.5);
  for (std::size_t k = 1; k < knots.size(); ++k) CHECK(knots[k] > knots[k - 1]);
  const double mean = 2.5 / 100;
  CHECK(knots[1] - knots[0] == Approx(0.1 * mean).epsilon(0.02));
  CHECK(knots[100] - knots[99] == Approx(0.1 * mean).epsilon(0.02));
  CHECK(knots[51] - knots[50] == Approx(1.9 * mean).epsilon(0.02));
  const std::vector<double> uniform = gs::planning::throw_collocation_mesh(2.5, 10, 0.0);
  for (int k = 0; k <= 10; ++k) CHECK(uniform[k] == Approx(0.25 * k));
}

TEST_CASE("the NLP's gradient, Jacobian and Hessian match finite differences", "[throw_planner]") {
  // The fixed launch state of (34), and the free one of a throw to a target (target_throw.hpp).
  const bool to_target = GENERATE(false, true);
  ThrowProblem problem;
  if (to_target) {
    gs::planning::ThrowCatchTarget target;
    target.distance_m = 3.2;
    target.height_m = -0.4;
    problem.catch_target = target;
  }
  ThrowCollocationNlp nlp(problem, gs::planning::throw_collocation_mesh(problem.duration_s, 4, 0.5));
  Ipopt::Index n = 0, m = 0, nnz_jac = 0, nnz_h = 0;
  Ipopt::TNLP::IndexStyleEnum style;
  REQUIRE(nlp.get_nlp_info(n, m, nnz_jac, nnz_h, style));
  // The knots, each with its slacks, and the catching instant of a target throw.
  REQUIRE(n == 13 * 5 + (to_target ? 1 : 0));
  // Per interval Simpson, F_N and slew rows; F_N at inner knots; F_N at T and the catch rows.
  REQUIRE(m == 10 * 4 + 3 + (to_target ? 4 : 0));

  // A generic point: the straight line with a deterministic wiggle in every variable.
  Eigen::VectorXd x = nlp.initial_guess();
  for (int i = 0; i < n; ++i) x(i) += 0.1 * std::sin(0.7 * i + 0.3);
  Eigen::VectorXd lambda(m);
  for (int r = 0; r < m; ++r) lambda(r) = std::cos(1.1 * r + 0.2);
  const double sigma = 0.7;

  const auto objective = [&](const Eigen::VectorXd& xx) {
    double f = 0.0;
    nlp.eval_f(n, xx.data(), true, f);
    return f;
  };
  const auto constraints = [&](const Eigen::VectorXd& xx) {
    Eigen::VectorXd g(m);
    nlp.eval_g(n, xx.data(), true, m, g.data());
    return g;
  };
  const auto dense_jacobian = [&](const Eigen::VectorXd& xx) {
    std::vector<Ipopt::Index> rows(nnz_jac), cols(nnz_jac);
    nlp.eval_jac_g(n, nullptr, true, m, nnz_jac, rows.data(), cols.data(), nullptr);
    std::vector<double> values(nnz_jac);
    nlp.eval_jac_g(n, xx.data(), true, m, nnz_jac, nullptr, nullptr, values.data());
    Eigen::MatrixXd J = Eigen::MatrixXd::Zero(m, n);
    for (int e = 0; e < nnz_jac; ++e) J(rows[e], cols[e]) += values[e];
    return J;
  };
  const auto lagrangian_gradient = [&](const Eigen::VectorXd& xx) {
    Eigen::VectorXd grad(n);
    nlp.eval_grad_f(n, xx.data(), true, grad.data());
    return Eigen::VectorXd(sigma * grad + dense_jacobian(xx).transpose() * lambda);
  };

  Eigen::VectorXd grad(n);
  nlp.eval_grad_f(n, x.data(), true, grad.data());
  const Eigen::MatrixXd J = dense_jacobian(x);
  std::vector<Ipopt::Index> hrows(nnz_h), hcols(nnz_h);
  nlp.eval_h(n, nullptr, true, sigma, m, nullptr, true, nnz_h, hrows.data(), hcols.data(), nullptr);
  std::vector<double> hvalues(nnz_h);
  nlp.eval_h(n, x.data(), true, sigma, m, lambda.data(), true, nnz_h, nullptr, nullptr, hvalues.data());
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(n, n);
  for (int e = 0; e < nnz_h; ++e) {
    REQUIRE(hrows[e] >= hcols[e]);  // lower triangle, as IPOPT wants
    H(hrows[e], hcols[e]) += hvalues[e];
    if (hrows[e] != hcols[e]) H(hcols[e], hrows[e]) += hvalues[e];
  }

  const double eps = 1e-6;
  double grad_err = 0.0, jac_err = 0.0, hess_err = 0.0;
  for (int i = 0; i < n; ++i) {
    Eigen::VectorXd xp = x, xm = x;
    xp(i) += eps;
    xm(i) -= eps;
    grad_err = std::max(grad_err, std::abs((objective(xp) - objective(xm)) / (2 * eps) - grad(i)));
    jac_err =
        std::max(jac_err, ((constraints(xp) - constraints(xm)) / (2 * eps) - J.col(i)).cwiseAbs().maxCoeff());
    hess_err = std::max(
        hess_err,
        ((lagrangian_gradient(xp) - lagrangian_gradient(xm)) / (2 * eps) - H.col(i)).cwiseAbs().maxCoeff());
  }
  CHECK(grad_err < 1e-6);
  CHECK(jac_err < 1e-6);
  CHECK(hess_err < 1e-5);
  // The Hessian is not trivially zero: the pole and thrust terms are curved.
  CHECK(H.cwiseAbs().maxCoeff() > 0.1);
}

TEST_CASE("the launch input makes F_N vanish exactly at the end state", "[throw_planner]") {
  const ThrowProblem problem;
  CHECK(problem.validate().empty());
  const PlanarInput<double> u_T = problem.launch_input();
  CHECK(u_T(planar::kPitchRate) == 2.5);
  CHECK(gs::model::planar_normal_force_per_mass_mps2<double>(problem.launch_state, u_T) ==
        Approx(0.0).margin(1e-12));
  CHECK(u_T(planar::kThrust) - 4.48 == Approx(0.319).margin(1e-3));
}

TEST_CASE("the planned throw meets every constraint of (34)", "[throw_planner]") {
  const ThrowProblem problem;
  const ThrowPlan& plan = paper_plan();
  INFO(plan.status);
  REQUIRE(plan.success);
  CHECK(plan.ipopt_status == 0);
  CHECK(plan.max_violation <= 1e-6);
  CHECK(plan.iterations > 0);
  const ThrowTrajectory& traj = plan.trajectory;
  REQUIRE(traj.intervals() == 100);
  REQUIRE(traj.state.size() == 201);

  // Recompute everything from the returned points, independently of the NLP class.
  CHECK(throw_checks::max_collocation_defect(traj) < 1e-6);

  const gs::model::VehicleLimits& lim = problem.limits;
  double min_fn = 1e9;
  for (std::size_t j = 0; j < traj.state.size(); ++j) {
    const double a_q = traj.input[j](planar::kThrust);
    const double omega = traj.input[j](planar::kPitchRate);
    CHECK(a_q >= lim.a_q_min_mps2 - 1e-6);
    CHECK(a_q <= lim.a_q_max_mps2 + 1e-6);
    CHECK(std::abs(omega) <= lim.omega_max_radps + 1e-6);
    const double fn = gs::model::planar_normal_force_per_mass_mps2<double>(traj.state[j], traj.input[j]);
    CHECK(fn == Approx(traj.normal_force_per_mass_mps2[j]).margin(1e-12));
    min_fn = std::min(min_fn, fn);
  }
  CHECK(min_fn >= -1e-6);

  // Boundary conditions: hover at the origin, and the launch state with F_N = 0 exactly.
  CHECK(traj.t_s.front() == 0.0);
  CHECK(traj.t_s.back() == problem.duration_s);
  CHECK(traj.state.front().cwiseAbs().maxCoeff() <= 1e-9);
  CHECK(traj.input.front()(planar::kThrust) == Approx(pa::kGravity_mps2).margin(1e-9));
  CHECK(traj.input.front()(planar::kPitchRate) == Approx(0.0).margin(1e-9));
  CHECK((traj.state.back() - problem.launch_state).cwiseAbs().maxCoeff() <= 1e-9);
  CHECK(plan.end_state_error <= 1e-9);
  CHECK(traj.input.back()(planar::kThrust) == Approx(problem.launch_thrust_mps2()).margin(1e-9));
  CHECK(traj.input.back()(planar::kPitchRate) == Approx(2.5).margin(1e-9));
  CHECK(traj.normal_force_per_mass_mps2.back() == Approx(0.0).margin(1e-9));

  // The reported cost is the Simpson quadrature of (34)'s integrand over the points.
  const double cost = paper_cost(traj);
  CHECK(plan.cost == Approx(cost).epsilon(1e-9));
}

TEST_CASE("the throw is optimal: a finer mesh changes the cost little, and another feasible "
          "throw costs more",
          "[throw_planner]") {
  const ThrowPlan& plan = paper_plan();
  REQUIRE(plan.success);
  gs::planning::ThrowSolverOptions fine;
  fine.intervals = 200;
  const ThrowPlan finer = gs::planning::plan_throw(ThrowProblem{}, fine);
  REQUIRE(finer.success);
  CHECK(finer.cost == Approx(plan.cost).epsilon(0.01));
  // Another feasible throw, the optimum for a doubled pitch-rate weight, evaluated under the
  // weights of (34).
  ThrowProblem heavy;
  heavy.weights.pitch_rate = 16.0;
  const ThrowPlan other = gs::planning::plan_throw(heavy);
  REQUIRE(other.success);
  const double other_cost = paper_cost(other.trajectory);
  CHECK(other_cost > plan.cost);
}

TEST_CASE("the trajectory's interpolants pass through its collocation points", "[throw_planner]") {
  const ThrowTrajectory& traj = paper_plan().trajectory;
  REQUIRE(!traj.t_s.empty());
  for (std::size_t j = 0; j < traj.t_s.size(); ++j) {
    // Knots exactly; midpoints through the Hermite constraint of the transcription.
    CHECK((traj.state_at(traj.t_s[j]) - traj.state[j]).cwiseAbs().maxCoeff() < 1e-6);
    CHECK((traj.input_at(traj.t_s[j]) - traj.input[j]).cwiseAbs().maxCoeff() < 1e-9);
  }
  CHECK((traj.state_at(-1.0) - traj.state.front()).norm() == 0.0);
  CHECK((traj.state_at(9.0) - traj.state.back()).norm() == 0.0);
}

TEST_CASE("flown open loop on the planar model, the pole stays on the plate until T and leaves "
          "there",
          "[throw_planner]") {
  const ThrowProblem problem;
  const ThrowPlan& plan = paper_plan();
  REQUIRE(plan.success);
  const ThrowTrajectory& traj = plan.trajectory;
  // RK4 with the interpolated inputs in 0.1 ms steps (the shortest interval is 2.5 ms).
  PlanarState<double> s = PlanarState<double>::Zero();
  const int steps = 25000;
  const double h = problem.duration_s / steps;
  double min_fn_early = 1e9;  // on [0, T - 0.1 s]
  double min_fn_all = 1e9;
  for (int k = 0; k < steps; ++k) {
    s = rk4_step(s, k * h, h, traj);
    const double t = (k + 1) * h;
    const double fn = gs::model::planar_normal_force_per_mass_mps2<double>(s, traj.input_at(t), traj.params);
    min_fn_all = std::min(min_fn_all, fn);
    if (t <= problem.duration_s - 0.1) min_fn_early = std::min(min_fn_early, fn);
  }
  // The pole is pressed firmly onto the plate throughout the throw; over the last 0.1 s the
  // thrust ramps down to a_q,T at the slew limit and F_N falls smoothly to 0 ...
  CHECK(min_fn_early > 2.0);
  CHECK(min_fn_all >= -1e-3);
  // ... and at T it is at the launch state. The tolerance is the transcription's error grown
  // over 2.5 s by the unstable pole (open-loop time constant sqrt(4L / 3g) = 0.3 s); measured
  // at N = 100 with end_refinement 0.9: about 1e-6 m, 2e-6 m/s, 1.4e-4 rad and 5e-4 rad/s.
  const PlanarState<double> err = s - problem.launch_state;
  CHECK(err.head<4>().cwiseAbs().maxCoeff() < 1e-4);
  CHECK(std::abs(err(planar::kTheta)) < 1e-5);
  CHECK(std::abs(err(planar::kAlpha)) < 1e-3);
  CHECK(std::abs(err(planar::kAlphaDot)) < 5e-3);
  const double fn_T =
      gs::model::planar_normal_force_per_mass_mps2<double>(s, problem.launch_input(), traj.params);
  CHECK(std::abs(fn_T) < 1e-2);

  // Holding the launch input past T the normal force turns negative at once: the pole leaves.
  const PlanarInput<double> u_T = problem.launch_input();
  PlanarState<double> after = s;
  for (int k = 0; k < 100; ++k) {
    const auto f = [&](const PlanarState<double>& x) {
      return gs::model::planar_pole_vehicle_dynamics<double>(x, u_T);
    };
    const double hh = 1e-4;
    const PlanarState<double> k1 = f(after);
    const PlanarState<double> k2 = f(after + 0.5 * hh * k1);
    const PlanarState<double> k3 = f(after + 0.5 * hh * k2);
    const PlanarState<double> k4 = f(after + hh * k3);
    after += hh / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
  }
  CHECK(gs::model::planar_normal_force_per_mass_mps2<double>(after, u_T) < -0.05);
}

TEST_CASE("an ill-posed or infeasible throw is reported, not returned as a plan", "[throw_planner]") {
  ThrowProblem weak_motors;
  weak_motors.limits.a_q_min_mps2 = 5.0;  // the launch needs a_q,T = 4.80 m/s^2
  const ThrowPlan rejected = gs::planning::plan_throw(weak_motors);
  CHECK_FALSE(rejected.success);
  CHECK(rejected.status.find("rejected") != std::string::npos);

  ThrowProblem too_short;
  too_short.duration_s = 0.4;  // 2 m up and 5.5 m/s in 0.4 s needs far more than 20 m/s^2
  gs::planning::ThrowSolverOptions options;
  options.max_iterations = 100;
  const ThrowPlan failed = gs::planning::plan_throw(too_short, options);
  CHECK_FALSE(failed.success);
  CHECK(failed.ipopt_status != 0);

  gs::planning::ThrowSolverOptions bad;
  bad.intervals = 0;
  CHECK_FALSE(gs::planning::plan_throw(ThrowProblem{}, bad).success);
}
