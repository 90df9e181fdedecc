#include "groundstation/planning/throw_collocation_nlp.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <unsupported/Eigen/AutoDiff>

namespace gs::planning {
namespace {

namespace planar = model::planar;
constexpr int kP = ThrowCollocationNlp::kPointSize;
constexpr int kO = ThrowCollocationNlp::kOutputs;
constexpr int kS = planar::kStateSize;
constexpr int kV = ThrowCollocationNlp::kKnotSize;
constexpr int kSlack = ThrowCollocationNlp::kPointSize;  // a knot's first slack variable
// The slacks of knot k, after its point: F_N at the knot, F_N at interval k's midpoint, and
// interval k's thrust and pitch-rate slews.
constexpr int kKnotForceSlack = kSlack, kMidForceSlack = kSlack + 1, kSlewSlack = kSlack + 2;
constexpr double kInfinity = 2e19;  // IPOPT's default nlp_upper_bound_inf is 1e19
constexpr double kMinCatchTime_s = 0.1, kMaxCatchTime_s = 3.0;

// g(p) = (f(s, u), F_N(s, u) / m_p, running cost of (34)) for one collocation point.
template <typename Scalar>
Eigen::Matrix<Scalar, kO, 1> point_outputs(const Eigen::Matrix<Scalar, kP, 1>& p,
                                           const ThrowProblem& problem) {
  const model::PlanarState<Scalar> s = p.template head<kS>();
  const model::PlanarInput<Scalar> u = p.template tail<planar::kInputSize>();
  Eigen::Matrix<Scalar, kO, 1> out;
  out.template head<kS>() = model::planar_pole_vehicle_dynamics<Scalar>(s, u, problem.params);
  out(ThrowCollocationNlp::kNormalForceOutput) =
      model::planar_normal_force_per_mass_mps2<Scalar>(s, u, problem.params);
  const Scalar thrust_dev = u(planar::kThrust) - problem.params.gravity_mps2;
  out(ThrowCollocationNlp::kCostOutput) =
      problem.weights.alpha * s(planar::kAlpha) * s(planar::kAlpha) +
      problem.weights.thrust * thrust_dev * thrust_dev +
      problem.weights.pitch_rate * u(planar::kPitchRate) * u(planar::kPitchRate);
  return out;
}

// The value and Jacobian of outputs(v) (a generic callable, v in R^N) by one forward AD pass.
template <int N, int O, typename Outputs>
void forward_jacobian(const Outputs& outputs, const Eigen::Matrix<double, N, 1>& v,
                      Eigen::Matrix<double, O, 1>& value, Eigen::Matrix<double, O, N>& jacobian) {
  using Ad = Eigen::AutoDiffScalar<Eigen::Matrix<double, N, 1>>;
  Eigen::Matrix<Ad, N, 1> v_ad;
  for (int i = 0; i < N; ++i) v_ad(i) = Ad(v(i), N, i);
  const Eigen::Matrix<Ad, O, 1> out = outputs(v_ad);
  for (int o = 0; o < O; ++o) {
    value(o) = out(o).value();
    // A term that does not depend on any variable (a constant output) has empty derivatives.
    if (out(o).derivatives().size() == N) {
      jacobian.row(o) = out(o).derivatives().transpose();
    } else {
      jacobian.row(o).setZero();
    }
  }
}

// The Hessian of weights . outputs(v) over the variables `vars` (the others held constant), by
// forward-over-forward AD.
template <int D, int N, int O, typename Outputs>
Eigen::Matrix<double, D, D> weighted_hessian_of(const Outputs& outputs, const Eigen::Matrix<double, N, 1>& v,
                                                const Eigen::Matrix<double, O, 1>& weights,
                                                const std::array<int, D>& vars) {
  using Inner = Eigen::AutoDiffScalar<Eigen::Matrix<double, D, 1>>;
  using Outer = Eigen::AutoDiffScalar<Eigen::Matrix<Inner, D, 1>>;
  const Inner zero(0.0, Eigen::Matrix<double, D, 1>::Zero());
  Eigen::Matrix<Outer, N, 1> v_ad;
  for (int i = 0; i < N; ++i) {
    v_ad(i).value() = Inner(v(i), Eigen::Matrix<double, D, 1>::Zero());
    v_ad(i).derivatives().setConstant(zero);
  }
  for (int a = 0; a < D; ++a) {
    v_ad(vars[a]).value() = Inner(v(vars[a]), D, a);
    v_ad(vars[a]).derivatives()(a) = Inner(1.0, Eigen::Matrix<double, D, 1>::Zero());
  }
  const Eigen::Matrix<Outer, O, 1> out = outputs(v_ad);
  Eigen::Matrix<double, D, D> hessian = Eigen::Matrix<double, D, D>::Zero();
  for (int o = 0; o < O; ++o) {
    if (weights(o) == 0.0 || out(o).derivatives().size() != D) continue;
    for (int r = 0; r < D; ++r) {
      const Inner& d = out(o).derivatives()(r);
      if (d.derivatives().size() == D) hessian.row(r) += weights(o) * d.derivatives().transpose();
    }
  }
  return hessian;
}

void point_jacobian(const Eigen::Matrix<double, kP, 1>& p, const ThrowProblem& problem,
                    Eigen::Matrix<double, kO, 1>& value, Eigen::Matrix<double, kO, kP>& jacobian) {
  forward_jacobian<kP, kO>([&problem](const auto& v) { return point_outputs(v, problem); }, p, value,
                           jacobian);
}

template <int D>
Eigen::Matrix<double, D, D> weighted_hessian(const Eigen::Matrix<double, kP, 1>& p,
                                             const Eigen::Matrix<double, kO, 1>& weights,
                                             const ThrowProblem& problem, const std::array<int, D>& vars) {
  return weighted_hessian_of<D, kP, kO>([&problem](const auto& v) { return point_outputs(v, problem); }, p,
                                        weights, vars);
}

// The catch rows of a target throw as a function of q = (p_N, t_c).
constexpr int kQ = kP + 1;
template <typename Scalar>
Eigen::Matrix<Scalar, 3, 1> catch_outputs(const Eigen::Matrix<Scalar, kQ, 1>& q,
                                          const ThrowCatchTarget& target) {
  const model::PlanarState<Scalar> s = q.template head<kS>();
  return catch_target_residuals<Scalar>(s, q(kP), target);
}
// The catch rows are curved in the pole's launch velocity and tilt and in t_c; x and z only
// shift the flight.
constexpr std::array<int, 5> kCatchCurved = {planar::kVx, planar::kVz, planar::kAlpha, planar::kAlphaDot, kP};

// The variables the model is curved in: x, z and the velocities enter f, F_N and the cost only
// linearly, so the point Hessians live in this 5 x 5 block (25 second derivatives instead of 81
// per AD operation). The constructor checks this against the full Hessian.
constexpr std::array<int, 5> kCurved = {planar::kTheta, planar::kAlpha, planar::kAlphaDot,
                                        kS + planar::kThrust, kS + planar::kPitchRate};

Eigen::Matrix<double, kP, kP> point_hessian(const Eigen::Matrix<double, kP, 1>& p,
                                            const Eigen::Matrix<double, kO, 1>& weights,
                                            const ThrowProblem& problem) {
  const Eigen::Matrix<double, 5, 5> curved = weighted_hessian<5>(p, weights, problem, kCurved);
  Eigen::Matrix<double, kP, kP> hessian = Eigen::Matrix<double, kP, kP>::Zero();
  for (int r = 0; r < 5; ++r) {
    for (int c = 0; c < 5; ++c) hessian(kCurved[r], kCurved[c]) = curved(r, c);
  }
  return hessian;
}

// Throws when the model is curved outside kCurved (at a few points with no special values).
void check_curved_variables(const ThrowProblem& problem) {
  std::array<int, kP> all;
  for (int i = 0; i < kP; ++i) all[i] = i;
  for (int trial = 0; trial < 3; ++trial) {
    Eigen::Matrix<double, kP, 1> p;
    Eigen::Matrix<double, kO, 1> weights;
    for (int i = 0; i < kP; ++i) p(i) = 0.7 * std::sin(1.3 * i + 2.1 * trial + 0.4) + 0.05 * i;
    p(kS + planar::kThrust) = 7.0 + trial;  // a positive thrust
    for (int o = 0; o < kO; ++o) weights(o) = 1.0 + 0.37 * o + 0.11 * trial;
    Eigen::Matrix<double, kP, kP> outside = weighted_hessian<kP>(p, weights, problem, all);
    for (int r : kCurved) {
      for (int c : kCurved) outside(r, c) = 0.0;
    }
    if (outside.cwiseAbs().maxCoeff() != 0.0) {
      throw std::logic_error("the throw model is curved outside the variables the planner expects");
    }
  }
}

}  // namespace

std::vector<double> throw_collocation_mesh(double duration_s, int intervals, double end_refinement) {
  // t = T phi(sigma), phi(sigma) = sigma - r sin(2 pi sigma) / (2 pi): phi' = 1 - r cos(2 pi sigma)
  // is 1 - r at both ends and 1 + r in the middle.
  std::vector<double> knots(intervals + 1);
  const double two_pi = 2.0 * std::acos(-1.0);
  for (int k = 0; k <= intervals; ++k) {
    const double sigma = static_cast<double>(k) / intervals;
    knots[k] = duration_s * (sigma - end_refinement * std::sin(two_pi * sigma) / two_pi);
  }
  knots.front() = 0.0;
  knots.back() = duration_s;
  return knots;
}

ThrowCollocationNlp::ThrowCollocationNlp(const ThrowProblem& problem, std::vector<double> knots_s)
    : problem_(problem), intervals_(static_cast<int>(knots_s.size()) - 1), knots_s_(std::move(knots_s)) {
  check_curved_variables(problem_);
  // The structures, in the order eval_jac_g and eval_h write their values. Dense blocks (see
  // the header): an interval's rows on its first knot with its slacks and on its second knot's
  // point; a knot's row on the knot with its slacks.
  const auto var = [](int knot, int index) { return kV * knot + index; };
  const auto add_jac = [&](int row, int knot, int columns) {
    for (int d = 0; d < columns; ++d) {
      jac_rows_.push_back(row);
      jac_cols_.push_back(var(knot, d));
    }
  };
  for (int k = 0; k < intervals_; ++k) {
    for (int i = 0; i < kIntervalRows; ++i) add_jac(kIntervalRows * k + i, k, kV + kP);
  }
  for (int j = 1; j < intervals_; ++j) add_jac(knot_row(j), j, kV);
  if (has_target()) {
    // F_N(p_N), then the catch rows on (p_N, t_c).
    add_jac(knot_row(intervals_), intervals_, kP);
    for (int i = 1; i < kTerminalRows; ++i) {
      add_jac(knot_row(intervals_) + i, intervals_, kP);
      jac_rows_.push_back(knot_row(intervals_) + i);
      jac_cols_.push_back(catch_time_variable());
    }
  }
  for (int j = 0; j < knot_count(); ++j) {
    for (int r = 0; r < kP; ++r) {
      for (int c = 0; c <= r; ++c) {
        hess_rows_.push_back(var(j, r));
        hess_cols_.push_back(var(j, c));
      }
    }
  }
  for (int k = 0; k < intervals_; ++k) {
    for (int r = 0; r < kP; ++r) {
      for (int c = 0; c < kP; ++c) {
        hess_rows_.push_back(var(k + 1, r));
        hess_cols_.push_back(var(k, c));
      }
    }
  }
  if (has_target()) {
    for (int c = 0; c < kP; ++c) {
      hess_rows_.push_back(catch_time_variable());
      hess_cols_.push_back(var(intervals_, c));
    }
    hess_rows_.push_back(catch_time_variable());
    hess_cols_.push_back(catch_time_variable());
  }
}

void ThrowCollocationNlp::evaluate(const double* x, Evaluation& e) const {
  const int knots = knot_count();
  e.knot_value.resize(knots);
  e.knot_jacobian.resize(knots);
  e.mid_value.resize(intervals_);
  e.mid_jacobian.resize(intervals_);
  e.mid_point.resize(intervals_);
  e.mid_map.resize(intervals_);
  e.mid_total.resize(intervals_);
  for (int j = 0; j < knots; ++j) {
    point_jacobian(Eigen::Map<const PointVector>(x + kV * j), problem_, e.knot_value[j], e.knot_jacobian[j]);
  }
  for (int k = 0; k < intervals_; ++k) {
    const double h = interval_length(k);
    const Eigen::Map<const PointVector> p_a(x + kV * k), p_b(x + kV * (k + 1));
    PointVector& p_m = e.mid_point[k];
    p_m = 0.5 * (p_a + p_b);
    p_m.head<kS>() += h / 8.0 * (e.knot_value[k].head<kS>() - e.knot_value[k + 1].head<kS>());
    MidpointMap& map = e.mid_map[k];
    map.setZero();
    map.leftCols<kP>().diagonal().setConstant(0.5);
    map.rightCols<kP>().diagonal().setConstant(0.5);
    map.topLeftCorner<kS, kP>() += h / 8.0 * e.knot_jacobian[k].topRows<kS>();
    map.topRightCorner<kS, kP>() -= h / 8.0 * e.knot_jacobian[k + 1].topRows<kS>();
    point_jacobian(p_m, problem_, e.mid_value[k], e.mid_jacobian[k]);
    e.mid_total[k] = e.mid_jacobian[k].lazyProduct(map);
  }
  if (has_target()) {
    const ThrowCatchTarget& target = *problem_.catch_target;
    forward_jacobian<kQ, 3>([&target](const auto& q) { return catch_outputs(q, target); }, terminal_vector(x),
                            e.catch_value, e.catch_jacobian);
  }
}

ThrowCollocationNlp::TerminalVector ThrowCollocationNlp::terminal_vector(const double* x) const {
  TerminalVector q;
  q << Eigen::Map<const PointVector>(x + kV * intervals_), x[catch_time_variable()];
  return q;
}

void ThrowCollocationNlp::evaluate_cached(const double* x) {
  const Eigen::Map<const Eigen::VectorXd> xv(x, variable_count());
  if (cache_valid_ && cached_x_ == xv) return;
  evaluate(x, cache_);
  cached_x_ = xv;
  cache_valid_ = true;
}

double ThrowCollocationNlp::slew_limit(int k, int i) const {
  const double rate =
      i == planar::kThrust ? problem_.thrust_rate_max_mps3 : problem_.pitch_acceleration_max_radps2;
  return rate > 0.0 ? rate * interval_length(k) : kInfinity;
}

double ThrowCollocationNlp::point_time(int point) const {
  const int k = point / 2;
  return point % 2 == 0 ? knots_s_[k] : 0.5 * (knots_s_[k] + knots_s_[k + 1]);
}

void ThrowCollocationNlp::fixed_bounds(Eigen::VectorXd& lower, Eigen::VectorXd& upper) const {
  const int n = variable_count();
  lower.setConstant(n, -kInfinity);
  upper.setConstant(n, kInfinity);
  const model::VehicleLimits& lim = problem_.limits;
  for (int j = 0; j < knot_count(); ++j) {
    lower(kV * j + kS + planar::kThrust) = lim.a_q_min_mps2;
    upper(kV * j + kS + planar::kThrust) = lim.a_q_max_mps2;
    lower(kV * j + kS + planar::kPitchRate) = -lim.omega_max_radps;
    upper(kV * j + kS + planar::kPitchRate) = lim.omega_max_radps;
    // F_N >= 0 and the slew limits, on the slacks; the slacks without a row are fixed at 0.
    const bool inner = j > 0 && j < intervals_, has_interval = j < intervals_;
    lower(kV * j + kKnotForceSlack) = 0.0;
    upper(kV * j + kKnotForceSlack) = inner ? kInfinity : 0.0;
    lower(kV * j + kMidForceSlack) = 0.0;
    upper(kV * j + kMidForceSlack) = has_interval ? kInfinity : 0.0;
    for (int i = 0; i < planar::kInputSize; ++i) {
      const double limit = has_interval ? slew_limit(j, i) : 0.0;
      lower(kV * j + kSlewSlack + i) = -limit;
      upper(kV * j + kSlewSlack + i) = limit;
    }
  }
  // s(0) = 0 with the hover input; s(T) = s_T with u_T (F_N = 0 exactly).
  PointVector start, end;
  start << model::PlanarState<double>::Zero(), problem_.hover_input();
  end << problem_.launch_state, problem_.launch_input();
  lower.head<kP>() = start;
  upper.head<kP>() = start;
  if (has_target()) {
    // The end knot is free (its inputs in the box); the catching instant no earlier than the
    // catcher needs (ThrowCatchTarget::min_catch_time_s) and within the flight a catch-point
    // prediction covers (catch_point_predictor.hpp's 3 s horizon).
    lower(catch_time_variable()) = std::max(kMinCatchTime_s, problem_.catch_target->min_catch_time_s);
    upper(catch_time_variable()) = kMaxCatchTime_s;
    return;
  }
  lower.segment<kP>(kV * intervals_) = end;
  upper.segment<kP>(kV * intervals_) = end;
}

void ThrowCollocationNlp::set_warm_start(const ThrowTrajectory& trajectory, double catch_time_s) {
  warm_start_ = Eigen::VectorXd::Zero(variable_count());
  for (int j = 0; j <= intervals_; ++j) {
    warm_start_.segment<kS>(kV * j) = trajectory.state_at(knots_s_[j]);
    warm_start_.segment<planar::kInputSize>(kV * j + kS) = trajectory.input_at(knots_s_[j]);
  }
  if (has_target()) warm_start_(catch_time_variable()) = catch_time_s;
}

Eigen::VectorXd ThrowCollocationNlp::initial_guess() const {
  Eigen::VectorXd x = warm_start_;
  if (x.size() != variable_count()) {
    PointVector start, end;
    start << model::PlanarState<double>::Zero(), problem_.hover_input();
    end << problem_.launch_state, problem_.launch_input();
    x = Eigen::VectorXd::Zero(variable_count());
    for (int j = 0; j <= intervals_; ++j) {
      const double w = static_cast<double>(j) / intervals_;
      x.segment<kP>(kV * j) = (1.0 - w) * start + w * end;
    }
    if (has_target()) x(catch_time_variable()) = problem_.catch_target->catch_time_guess_s;
  }
  // The variables moved into their bounds, then the slacks at the values of their rows, moved
  // into theirs.
  Eigen::VectorXd lower, upper;
  fixed_bounds(lower, upper);
  x = x.cwiseMax(lower).cwiseMin(upper);
  Evaluation e;
  evaluate(x.data(), e);
  for (int j = 0; j <= intervals_; ++j) {
    x(kV * j + kKnotForceSlack) = e.knot_value[j](kNormalForceOutput);
    if (j < intervals_) {
      x(kV * j + kMidForceSlack) = e.mid_value[j](kNormalForceOutput);
      for (int i = 0; i < planar::kInputSize; ++i) {
        x(kV * j + kSlewSlack + i) = x(kV * (j + 1) + kS + i) - x(kV * j + kS + i);
      }
    }
    for (int d = kSlack; d < kV; ++d)
      x(kV * j + d) = std::clamp(x(kV * j + d), lower(kV * j + d), upper(kV * j + d));
  }
  return x;
}

ThrowTrajectory ThrowCollocationNlp::trajectory_from(const Eigen::VectorXd& x) const {
  Evaluation e;
  evaluate(x.data(), e);
  ThrowTrajectory traj;
  traj.params = problem_.params;
  for (int q = 0; q < point_count(); ++q) {
    const PointVector p = q % 2 == 0 ? PointVector(x.segment<kP>(kV * (q / 2))) : e.mid_point[q / 2];
    traj.t_s.push_back(point_time(q));
    traj.state.push_back(p.head<kS>());
    traj.input.push_back(p.tail<planar::kInputSize>());
    traj.normal_force_per_mass_mps2.push_back(model::planar_normal_force_per_mass_mps2<double>(
        traj.state.back(), traj.input.back(), problem_.params));
  }
  return traj;
}

double ThrowCollocationNlp::max_violation(const Eigen::VectorXd& x) const {
  // The constraints of (34) on the trajectory itself, not through the slacks.
  Evaluation e;
  evaluate(x.data(), e);
  Eigen::VectorXd g(constraint_count()), lower, upper;
  if (!constraints_from(x.data(), e, g.data())) return std::numeric_limits<double>::infinity();
  double worst = 0.0;
  for (int k = 0; k < intervals_; ++k) {
    worst = std::max(worst, g.segment<kS>(kIntervalRows * k).cwiseAbs().maxCoeff());
    worst = std::max(worst, -e.mid_value[k](kNormalForceOutput));
    for (int i = 0; i < planar::kInputSize; ++i) {
      const double slew = x(kV * (k + 1) + kS + i) - x(kV * k + kS + i);
      worst = std::max(worst, std::abs(slew) - slew_limit(k, i));
    }
  }
  // F_N >= 0 at every knot, the fixed end knots included.
  for (const OutputVector& v : e.knot_value) worst = std::max(worst, -v(kNormalForceOutput));
  if (has_target()) {
    worst = std::max(worst, g.tail<kTerminalRows>().cwiseAbs().maxCoeff());
  }
  fixed_bounds(lower, upper);
  if (has_target()) {
    const int t = catch_time_variable();
    worst = std::max({worst, lower(t) - x(t), x(t) - upper(t)});
  }
  for (int j = 0; j <= intervals_; ++j) {
    for (int d = 0; d < kP; ++d) {
      const int i = kV * j + d;
      worst = std::max({worst, lower(i) - x(i), x(i) - upper(i)});
    }
  }
  return worst;
}

bool ThrowCollocationNlp::get_nlp_info(Ipopt::Index& n, Ipopt::Index& m, Ipopt::Index& nnz_jac_g,
                                       Ipopt::Index& nnz_h_lag, IndexStyleEnum& index_style) {
  n = variable_count();
  m = constraint_count();
  nnz_jac_g = jacobian_nonzeros();
  nnz_h_lag = hessian_nonzeros();
  index_style = C_STYLE;
  return true;
}

bool ThrowCollocationNlp::get_bounds_info(Ipopt::Index n, Ipopt::Number* x_l, Ipopt::Number* x_u,
                                          Ipopt::Index m, Ipopt::Number* g_l, Ipopt::Number* g_u) {
  Eigen::VectorXd lower, upper;
  fixed_bounds(lower, upper);
  Eigen::Map<Eigen::VectorXd>(x_l, n) = lower;
  Eigen::Map<Eigen::VectorXd>(x_u, n) = upper;
  std::fill(g_l, g_l + m, 0.0);  // every row is an equality; the inequalities are on slacks
  std::fill(g_u, g_u + m, 0.0);
  return true;
}

bool ThrowCollocationNlp::get_starting_point(Ipopt::Index n, bool init_x, Ipopt::Number* x, bool init_z,
                                             Ipopt::Number*, Ipopt::Number*, Ipopt::Index, bool init_lambda,
                                             Ipopt::Number*) {
  if (!init_x || init_z || init_lambda) return false;
  Eigen::Map<Eigen::VectorXd>(x, n) = initial_guess();
  return true;
}

bool ThrowCollocationNlp::eval_f(Ipopt::Index, const Ipopt::Number* x, bool, Ipopt::Number& obj_value) {
  evaluate_cached(x);
  double sum = 0.0;
  for (int k = 0; k < intervals_; ++k) {
    sum += interval_length(k) / 6.0 *
           (cache_.knot_value[k](kCostOutput) + 4.0 * cache_.mid_value[k](kCostOutput) +
            cache_.knot_value[k + 1](kCostOutput));
  }
  obj_value = sum;
  return std::isfinite(sum);
}

bool ThrowCollocationNlp::eval_grad_f(Ipopt::Index n, const Ipopt::Number* x, bool, Ipopt::Number* grad_f) {
  evaluate_cached(x);
  Eigen::Map<Eigen::VectorXd> grad(grad_f, n);
  grad.setZero();
  for (int k = 0; k < intervals_; ++k) {
    const double h = interval_length(k);
    const auto mid = cache_.mid_total[k].row(kCostOutput);
    grad.segment<kP>(kV * k) +=
        h / 6.0 * (cache_.knot_jacobian[k].row(kCostOutput) + 4.0 * mid.head<kP>()).transpose();
    grad.segment<kP>(kV * (k + 1)) +=
        h / 6.0 * (cache_.knot_jacobian[k + 1].row(kCostOutput) + 4.0 * mid.tail<kP>()).transpose();
  }
  return true;
}

bool ThrowCollocationNlp::eval_g(Ipopt::Index, const Ipopt::Number* x, bool, Ipopt::Index, Ipopt::Number* g) {
  evaluate_cached(x);
  return constraints_from(x, cache_, g);
}

bool ThrowCollocationNlp::constraints_from(const double* x, const Evaluation& e, double* g) const {
  for (int k = 0; k < intervals_; ++k) {
    const double h = interval_length(k);
    const double* knot_a = x + kV * k;
    const double* knot_b = x + kV * (k + 1);
    double* row = g + kIntervalRows * k;
    Eigen::Map<model::PlanarState<double>> defect(row);
    defect =
        Eigen::Map<const model::PlanarState<double>>(knot_b) -
        Eigen::Map<const model::PlanarState<double>>(knot_a) -
        h / 6.0 *
            (e.knot_value[k].head<kS>() + 4.0 * e.mid_value[k].head<kS>() + e.knot_value[k + 1].head<kS>());
    row[kS] = e.mid_value[k](kNormalForceOutput) - knot_a[kMidForceSlack];
    for (int i = 0; i < planar::kInputSize; ++i) {
      row[kS + 1 + i] = knot_b[kS + i] - knot_a[kS + i] - knot_a[kSlewSlack + i];
    }
  }
  for (int j = 1; j < intervals_; ++j) {
    g[knot_row(j)] = e.knot_value[j](kNormalForceOutput) - x[kV * j + kKnotForceSlack];
  }
  if (has_target()) {
    g[knot_row(intervals_)] = e.knot_value[intervals_](kNormalForceOutput);
    for (int i = 0; i < 3; ++i) g[knot_row(intervals_) + 1 + i] = e.catch_value(i);
  }
  for (int r = 0; r < constraint_count(); ++r) {
    if (!std::isfinite(g[r])) return false;
  }
  return true;
}

bool ThrowCollocationNlp::eval_jac_g(Ipopt::Index, const Ipopt::Number* x, bool, Ipopt::Index,
                                     Ipopt::Index nele_jac, Ipopt::Index* iRow, Ipopt::Index* jCol,
                                     Ipopt::Number* values) {
  if (values == nullptr) {
    std::copy(jac_rows_.begin(), jac_rows_.end(), iRow);
    std::copy(jac_cols_.begin(), jac_cols_.end(), jCol);
    return true;
  }
  evaluate_cached(x);
  // Each row as its dense block of the structure: (knot a, its slacks, knot b's point).
  Eigen::Matrix<double, 1, kV + kP> row;
  double* out = values;
  const auto put = [&out](const auto& r) {
    for (int d = 0; d < r.size(); ++d) *out++ = r(d);
  };
  for (int k = 0; k < intervals_; ++k) {
    const SimpsonJacobian simpson = simpson_jacobian(k, cache_);
    for (int i = 0; i < kS; ++i) {
      row.setZero();
      row.segment<kP>(0) = simpson.row(i).head<kP>();
      row.segment<kP>(kV) = simpson.row(i).tail<kP>();
      put(row);
    }
    const auto force = cache_.mid_total[k].row(kNormalForceOutput);
    row.setZero();
    row.segment<kP>(0) = force.head<kP>();
    row.segment<kP>(kV) = force.tail<kP>();
    row(kMidForceSlack) = -1.0;
    put(row);
    for (int i = 0; i < planar::kInputSize; ++i) {
      row.setZero();
      row(kV + kS + i) = 1.0;
      row(kS + i) = -1.0;
      row(kSlewSlack + i) = -1.0;
      put(row);
    }
  }
  for (int j = 1; j < intervals_; ++j) {
    Eigen::Matrix<double, 1, kV> knot_row = Eigen::Matrix<double, 1, kV>::Zero();
    knot_row.head<kP>() = cache_.knot_jacobian[j].row(kNormalForceOutput);
    knot_row(kKnotForceSlack) = -1.0;
    put(knot_row);
  }
  if (has_target()) {
    put(cache_.knot_jacobian[intervals_].row(kNormalForceOutput));
    for (int i = 0; i < 3; ++i) put(cache_.catch_jacobian.row(i));
  }
  return out - values == nele_jac;
}

ThrowCollocationNlp::SimpsonJacobian ThrowCollocationNlp::simpson_jacobian(int k, const Evaluation& e) const {
  // d/d(p_a, p_b) of s_b - s_a - h/6 (f_a + 4 f(p_m) + f_b).
  const double h = interval_length(k);
  SimpsonJacobian jac = -4.0 * h / 6.0 * e.mid_total[k].topRows<kS>();
  jac.leftCols<kP>() -= h / 6.0 * e.knot_jacobian[k].topRows<kS>();
  jac.rightCols<kP>() -= h / 6.0 * e.knot_jacobian[k + 1].topRows<kS>();
  jac.leftCols<kS>().diagonal().array() -= 1.0;
  jac.middleCols<kS>(kP).diagonal().array() += 1.0;
  return jac;
}

bool ThrowCollocationNlp::eval_h(Ipopt::Index, const Ipopt::Number* x, bool, Ipopt::Number obj_factor,
                                 Ipopt::Index, const Ipopt::Number* lambda, bool, Ipopt::Index nele_hess,
                                 Ipopt::Index* iRow, Ipopt::Index* jCol, Ipopt::Number* values) {
  if (values == nullptr) {
    std::copy(hess_rows_.begin(), hess_rows_.end(), iRow);
    std::copy(hess_cols_.begin(), hess_cols_.end(), jCol);
    return true;
  }
  evaluate_cached(x);
  hessian_blocks(x, cache_, obj_factor, lambda, hess_diagonal_, hess_coupling_);
  if (has_target()) {
    // The catch rows' curvature in (p_N, t_c); its p_N block joins knot N's.
    const ThrowCatchTarget& target = *problem_.catch_target;
    const Eigen::Vector3d weights = Eigen::Map<const Eigen::Vector3d>(lambda + knot_row(intervals_) + 1);
    const Eigen::Matrix<double, 5, 5> curved =
        weighted_hessian_of<5, kQ, 3>([&target](const auto& q) { return catch_outputs(q, target); },
                                      terminal_vector(x), weights, kCatchCurved);
    hess_terminal_.setZero();
    for (int r = 0; r < 5; ++r) {
      for (int c = 0; c < 5; ++c) hess_terminal_(kCatchCurved[r], kCatchCurved[c]) = curved(r, c);
    }
    hess_diagonal_[intervals_] += hess_terminal_.topLeftCorner<kP, kP>();
  }
  double* out = values;
  for (int j = 0; j < knot_count(); ++j) {
    for (int r = 0; r < kP; ++r) {
      for (int c = 0; c <= r; ++c) {
        *out++ = hess_diagonal_[j](r, c);
      }
    }
  }
  for (int k = 0; k < intervals_; ++k) {
    for (int r = 0; r < kP; ++r) {
      for (int c = 0; c < kP; ++c) {
        *out++ = hess_coupling_[k](r, c);
      }
    }
  }
  if (has_target()) {
    for (int c = 0; c <= kP; ++c) *out++ = hess_terminal_(kP, c);
  }
  return out - values == nele_hess;
}

void ThrowCollocationNlp::hessian_blocks(const double* x, const Evaluation& e, double obj_factor,
                                         const double* lambda, std::vector<Block>& diagonal,
                                         std::vector<Block>& coupling) const {
  // The weight of each knot's outputs in the Lagrangian, and the Hessian blocks.
  std::vector<OutputVector> knot_weight(knot_count(), OutputVector::Zero());
  diagonal.assign(knot_count(), Block::Zero());
  coupling.resize(intervals_);  // rows of knot k + 1, columns of knot k
  for (int k = 0; k < intervals_; ++k) {
    const double h = interval_length(k);
    const Eigen::Map<const model::PlanarState<double>> simpson(lambda + kIntervalRows * k);
    OutputVector w_m = OutputVector::Zero();
    w_m.head<kS>() = -4.0 * h / 6.0 * simpson;
    w_m(kNormalForceOutput) = lambda[kIntervalRows * k + kS];
    w_m(kCostOutput) = obj_factor * 4.0 * h / 6.0;
    for (int j : {k, k + 1}) {
      knot_weight[j].head<kS>() -= h / 6.0 * simpson;
      knot_weight[j](kCostOutput) += obj_factor * h / 6.0;
    }
    // p_m is curved in the knots through h/8 (f_a - f_b): that curvature, weighted by the
    // Lagrangian's slope along p_m, is a term of the knots' own f weights.
    const PointVector slope = e.mid_jacobian[k].transpose() * w_m;
    knot_weight[k].head<kS>() += h / 8.0 * slope.head<kS>();
    knot_weight[k + 1].head<kS>() -= h / 8.0 * slope.head<kS>();
    // The rest is the midpoint's Hessian carried through d p_m / d(p_a, p_b). Coefficient-based
    // products: Eigen's blocked GEMM costs more than the arithmetic at 9 x 9.
    const Block hess_m = point_hessian(e.mid_point[k], w_m, problem_);
    const auto map_a = e.mid_map[k].leftCols<kP>();
    const auto map_b = e.mid_map[k].rightCols<kP>();
    const Block ha = hess_m.lazyProduct(map_a), hb = hess_m.lazyProduct(map_b);
    diagonal[k] += map_a.transpose().lazyProduct(ha);
    diagonal[k + 1] += map_b.transpose().lazyProduct(hb);
    coupling[k] = map_b.transpose().lazyProduct(ha);
  }
  for (int j = 1; j < intervals_; ++j) {
    knot_weight[j](kNormalForceOutput) = lambda[knot_row(j)];
  }
  if (has_target()) knot_weight[intervals_](kNormalForceOutput) = lambda[knot_row(intervals_)];
  for (int j = 0; j < knot_count(); ++j) {
    diagonal[j] += point_hessian(Eigen::Map<const PointVector>(x + kV * j), knot_weight[j], problem_);
  }
}

void ThrowCollocationNlp::finalize_solution(Ipopt::SolverReturn, Ipopt::Index n, const Ipopt::Number* x,
                                            const Ipopt::Number*, const Ipopt::Number*, Ipopt::Index,
                                            const Ipopt::Number*, const Ipopt::Number*,
                                            Ipopt::Number obj_value, const Ipopt::IpoptData*,
                                            Ipopt::IpoptCalculatedQuantities*) {
  solution_ = Eigen::Map<const Eigen::VectorXd>(x, n);
  solution_objective_ = obj_value;
}

}  // namespace gs::planning
