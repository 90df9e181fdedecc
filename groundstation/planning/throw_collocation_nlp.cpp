#include "groundstation/planning/throw_collocation_nlp.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <unsupported/Eigen/AutoDiff>

namespace gs::planning {
namespace {

namespace planar = model::planar;
constexpr int kP = ThrowCollocationNlp::kPointSize;
constexpr int kO = ThrowCollocationNlp::kOutputs;
constexpr int kS = planar::kStateSize;
constexpr double kInfinity = 2e19;  // IPOPT's default nlp_upper_bound_inf is 1e19

// g(p) = (f(s, u), F_N(s, u) / m_p, running cost of (34)) for one collocation point.
template <typename Scalar>
Eigen::Matrix<Scalar, kO, 1> pointOutputs(const Eigen::Matrix<Scalar, kP, 1>& p,
                                          const ThrowProblem& problem) {
  const model::PlanarState<Scalar> s = p.template head<kS>();
  const model::PlanarInput<Scalar> u = p.template tail<planar::kInputSize>();
  Eigen::Matrix<Scalar, kO, 1> out;
  out.template head<kS>() = model::planarPoleVehicleDynamics<Scalar>(s, u, problem.params);
  out(ThrowCollocationNlp::kNormalForceOutput) =
      model::planarNormalForcePerMass_mps2<Scalar>(s, u, problem.params);
  const Scalar thrust_dev = u(planar::kThrust) - problem.params.gravity_mps2;
  out(ThrowCollocationNlp::kCostOutput) =
      problem.weights.alpha * s(planar::kAlpha) * s(planar::kAlpha) +
      problem.weights.thrust * thrust_dev * thrust_dev +
      problem.weights.pitch_rate * u(planar::kPitchRate) * u(planar::kPitchRate);
  return out;
}

using Ad = Eigen::AutoDiffScalar<Eigen::Matrix<double, kP, 1>>;
using Ad2 = Eigen::AutoDiffScalar<Eigen::Matrix<Ad, kP, 1>>;

void pointJacobian(const Eigen::Matrix<double, kP, 1>& p, const ThrowProblem& problem,
                   Eigen::Matrix<double, kO, 1>& value, Eigen::Matrix<double, kO, kP>& jacobian) {
  Eigen::Matrix<Ad, kP, 1> p_ad;
  for (int i = 0; i < kP; ++i) p_ad(i) = Ad(p(i), kP, i);
  const Eigen::Matrix<Ad, kO, 1> out = pointOutputs<Ad>(p_ad, problem);
  for (int o = 0; o < kO; ++o) {
    value(o) = out(o).value();
    // A term that does not depend on any variable (a constant output) has empty derivatives.
    if (out(o).derivatives().size() == kP) {
      jacobian.row(o) = out(o).derivatives().transpose();
    } else {
      jacobian.row(o).setZero();
    }
  }
}

// The Hessian of weights . g(p), by forward-over-forward AD.
Eigen::Matrix<double, kP, kP> pointHessian(const Eigen::Matrix<double, kP, 1>& p,
                                           const Eigen::Matrix<double, kO, 1>& weights,
                                           const ThrowProblem& problem) {
  Eigen::Matrix<Ad2, kP, 1> p_ad;
  for (int i = 0; i < kP; ++i) {
    p_ad(i).value() = Ad(p(i), kP, i);
    for (int j = 0; j < kP; ++j) {
      p_ad(i).derivatives()(j) = Ad(i == j ? 1.0 : 0.0, Eigen::Matrix<double, kP, 1>::Zero());
    }
  }
  const Eigen::Matrix<Ad2, kO, 1> out = pointOutputs<Ad2>(p_ad, problem);
  Eigen::Matrix<double, kP, kP> hessian = Eigen::Matrix<double, kP, kP>::Zero();
  for (int o = 0; o < kO; ++o) {
    if (weights(o) == 0.0 || out(o).derivatives().size() != kP) continue;
    for (int r = 0; r < kP; ++r) {
      const Ad& d = out(o).derivatives()(r);
      if (d.derivatives().size() == kP) hessian.row(r) += weights(o) * d.derivatives().transpose();
    }
  }
  return hessian;
}

// A few points and weights with no special values, to read the sparsity off the derivatives.
Eigen::Matrix<double, kP, 1> genericPoint(int trial) {
  Eigen::Matrix<double, kP, 1> p;
  for (int i = 0; i < kP; ++i) p(i) = 0.7 * std::sin(1.3 * i + 2.1 * trial + 0.4) + 0.05 * i;
  p(kS + planar::kThrust) = 7.0 + trial;  // a positive thrust
  return p;
}

}  // namespace

std::vector<double> throwCollocationMesh(double duration_s, int intervals, double end_refinement) {
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

ThrowCollocationNlp::ThrowCollocationNlp(const ThrowProblem& problem,
                                         std::vector<double> knots_s)
    : problem_(problem),
      intervals_(static_cast<int>(knots_s.size()) - 1),
      knots_s_(std::move(knots_s)) {
  // Dependency and curvature patterns from AD at generic points.
  output_deps_.assign(kO, {});
  Eigen::Matrix<bool, kO, kP> depends = Eigen::Matrix<bool, kO, kP>::Constant(false);
  Eigen::Matrix<bool, kP, kP> curved = Eigen::Matrix<bool, kP, kP>::Constant(false);
  for (int trial = 0; trial < 3; ++trial) {
    const PointVector p = genericPoint(trial);
    OutputVector value;
    PointJacobian jac;
    pointJacobian(p, problem_, value, jac);
    depends = depends.array() || (jac.array() != 0.0);
    OutputVector weights;
    for (int o = 0; o < kO; ++o) weights(o) = 1.0 + 0.37 * o + 0.11 * trial;
    curved = curved.array() || (pointHessian(p, weights, problem_).array() != 0.0);
  }
  for (int o = 0; o < kO; ++o) {
    for (int i = 0; i < kP; ++i) {
      if (depends(o, i)) output_deps_[o].push_back(i);
    }
  }
  for (int r = 0; r < kP; ++r) {
    for (int c = 0; c <= r; ++c) {
      if (curved(r, c) || curved(c, r)) hess_pattern_.emplace_back(r, c);
    }
  }

  // Jacobian structure, with repeated (row, col) pairs merged into one nonzero.
  std::map<std::pair<int, int>, int> slot_of;
  forEachJacobianEntry(false, [&](int row, int col, double) {
    const auto [it, inserted] =
        slot_of.emplace(std::make_pair(row, col), static_cast<int>(jac_rows_.size()));
    if (inserted) {
      jac_rows_.push_back(row);
      jac_cols_.push_back(col);
    }
    jac_slot_.push_back(it->second);
  });

  for (int j = 0; j < pointCount(); ++j) {
    for (const auto& [r, c] : hess_pattern_) {
      hess_rows_.push_back(kP * j + r);
      hess_cols_.push_back(kP * j + c);
    }
  }

  values_.resize(pointCount());
  jacobians_.resize(pointCount());
  for (auto& jac : jacobians_) jac.setZero();
  for (auto& v : values_) v.setZero();
}

template <typename Emit>
void ThrowCollocationNlp::forEachJacobianEntry(bool with_values, Emit&& emit) const {
  const auto var = [](int point, int index) { return kP * point + index; };
  const auto jac = [&](int point, int output, int index) {
    return with_values ? jacobians_[point](output, index) : 0.0;
  };
  for (int k = 0; k < intervals_; ++k) {
    const int a = 2 * k, m = 2 * k + 1, b = 2 * k + 2;
    const double h = intervalLength(k);
    for (int i = 0; i < kS; ++i) {
      const int simpson_row = 14 * k + i;
      emit(simpson_row, var(b, i), 1.0);
      emit(simpson_row, var(a, i), -1.0);
      for (int d : output_deps_[i]) {
        emit(simpson_row, var(a, d), -h / 6.0 * jac(a, i, d));
        emit(simpson_row, var(m, d), -4.0 * h / 6.0 * jac(m, i, d));
        emit(simpson_row, var(b, d), -h / 6.0 * jac(b, i, d));
      }
      const int hermite_row = 14 * k + kS + i;
      emit(hermite_row, var(m, i), 1.0);
      emit(hermite_row, var(a, i), -0.5);
      emit(hermite_row, var(b, i), -0.5);
      for (int d : output_deps_[i]) {
        emit(hermite_row, var(a, d), -h / 8.0 * jac(a, i, d));
        emit(hermite_row, var(b, d), h / 8.0 * jac(b, i, d));
      }
    }
  }
  for (int j = 1; j < pointCount() - 1; ++j) {
    const int row = 14 * intervals_ + (j - 1);
    for (int d : output_deps_[kNormalForceOutput]) {
      emit(row, var(j, d), jac(j, kNormalForceOutput, d));
    }
  }
  for (int j = 0; j + 1 < pointCount(); ++j) {
    for (int i = 0; i < planar::kInputSize; ++i) {
      emit(slewRow(j, i), var(j + 1, kS + i), 1.0);
      emit(slewRow(j, i), var(j, kS + i), -1.0);
    }
  }
}

double ThrowCollocationNlp::slewLimit(int row) const {
  const int j = (row - slewRow(0, 0)) / 2, i = (row - slewRow(0, 0)) % 2;
  const double rate = i == planar::kThrust ? problem_.thrust_rate_max_mps3
                                           : problem_.pitch_acceleration_max_radps2;
  return rate > 0.0 ? rate * (pointTime(j + 1) - pointTime(j)) : kInfinity;
}

void ThrowCollocationNlp::evaluatePoints(const double* x) {
  const int n = variableCount();
  const Eigen::Map<const Eigen::VectorXd> xv(x, n);
  if (cache_valid_ && cached_x_.size() == n && cached_x_ == xv) return;
  for (int j = 0; j < pointCount(); ++j) {
    const PointVector p = xv.segment<kP>(kP * j);
    pointJacobian(p, problem_, values_[j], jacobians_[j]);
  }
  cached_x_ = xv;
  cache_valid_ = true;
}

double ThrowCollocationNlp::quadratureWeight(int point) const {
  if (point % 2 == 1) return 4.0 * intervalLength((point - 1) / 2) / 6.0;
  const int k = point / 2;
  double w = 0.0;
  if (k < intervals_) w += intervalLength(k) / 6.0;
  if (k > 0) w += intervalLength(k - 1) / 6.0;
  return w;
}

double ThrowCollocationNlp::pointTime(int point) const {
  const int k = point / 2;
  return point % 2 == 0 ? knots_s_[k] : 0.5 * (knots_s_[k] + knots_s_[k + 1]);
}

void ThrowCollocationNlp::fixedBounds(Eigen::VectorXd& lower, Eigen::VectorXd& upper) const {
  const int n = variableCount();
  lower.setConstant(n, -kInfinity);
  upper.setConstant(n, kInfinity);
  const model::VehicleLimits& lim = problem_.limits;
  for (int j = 0; j < pointCount(); ++j) {
    lower(kP * j + kS + planar::kThrust) = lim.a_q_min_mps2;
    upper(kP * j + kS + planar::kThrust) = lim.a_q_max_mps2;
    lower(kP * j + kS + planar::kPitchRate) = -lim.omega_max_radps;
    upper(kP * j + kS + planar::kPitchRate) = lim.omega_max_radps;
  }
  // s(0) = 0 with the hover input; s(T) = s_T with u_T (F_N = 0 exactly).
  PointVector start, end;
  start << model::PlanarState<double>::Zero(), problem_.hoverInput();
  end << problem_.launch_state, problem_.launchInput();
  lower.head<kP>() = start;
  upper.head<kP>() = start;
  lower.tail<kP>() = end;
  upper.tail<kP>() = end;
}

Eigen::VectorXd ThrowCollocationNlp::initialGuess() const {
  PointVector start, end;
  start << model::PlanarState<double>::Zero(), problem_.hoverInput();
  end << problem_.launch_state, problem_.launchInput();
  Eigen::VectorXd x(variableCount());
  const int last = pointCount() - 1;
  for (int j = 0; j <= last; ++j) {
    const double w = static_cast<double>(j) / last;
    x.segment<kP>(kP * j) = (1.0 - w) * start + w * end;
  }
  return x;
}

ThrowTrajectory ThrowCollocationNlp::trajectoryFrom(const Eigen::VectorXd& x) const {
  ThrowTrajectory traj;
  traj.params = problem_.params;
  for (int j = 0; j < pointCount(); ++j) {
    const PointVector p = x.segment<kP>(kP * j);
    traj.t_s.push_back(pointTime(j));
    traj.state.push_back(p.head<kS>());
    traj.input.push_back(p.tail<planar::kInputSize>());
    traj.normal_force_per_mass_mps2.push_back(model::planarNormalForcePerMass_mps2<double>(
        traj.state.back(), traj.input.back(), problem_.params));
  }
  return traj;
}

double ThrowCollocationNlp::maxViolation(const Eigen::VectorXd& x) const {
  const int n = variableCount(), m = constraintCount();
  std::vector<OutputVector> values(pointCount());
  for (int j = 0; j < pointCount(); ++j) {
    values[j] = pointOutputs<double>(x.segment<kP>(kP * j), problem_);
  }
  Eigen::VectorXd g(m), lower, upper;
  if (!constraintsFrom(x.data(), values, g.data())) return std::numeric_limits<double>::infinity();
  double worst = 0.0;
  for (int r = 0; r < 14 * intervals_; ++r) worst = std::max(worst, std::abs(g(r)));
  // F_N >= 0 at every point, the fixed end points included.
  for (int j = 0; j < pointCount(); ++j) worst = std::max(worst, -values[j](kNormalForceOutput));
  for (int r = slewRow(0, 0); r < m; ++r) {
    worst = std::max(worst, std::abs(g(r)) - slewLimit(r));
  }
  fixedBounds(lower, upper);
  for (int i = 0; i < n; ++i) worst = std::max({worst, lower(i) - x(i), x(i) - upper(i)});
  return worst;
}

bool ThrowCollocationNlp::get_nlp_info(Ipopt::Index& n, Ipopt::Index& m, Ipopt::Index& nnz_jac_g,
                                       Ipopt::Index& nnz_h_lag, IndexStyleEnum& index_style) {
  n = variableCount();
  m = constraintCount();
  nnz_jac_g = jacobianNonzeros();
  nnz_h_lag = hessianNonzeros();
  index_style = C_STYLE;
  return true;
}

bool ThrowCollocationNlp::get_bounds_info(Ipopt::Index n, Ipopt::Number* x_l,
                                          Ipopt::Number* x_u, Ipopt::Index m,
                                          Ipopt::Number* g_l, Ipopt::Number* g_u) {
  Eigen::VectorXd lower, upper;
  fixedBounds(lower, upper);
  Eigen::Map<Eigen::VectorXd>(x_l, n) = lower;
  Eigen::Map<Eigen::VectorXd>(x_u, n) = upper;
  for (int r = 0; r < slewRow(0, 0); ++r) {
    const bool is_defect = r < 14 * intervals_;
    g_l[r] = 0.0;
    g_u[r] = is_defect ? 0.0 : kInfinity;
  }
  for (int r = slewRow(0, 0); r < m; ++r) {
    const double limit = slewLimit(r);
    g_l[r] = -limit;
    g_u[r] = limit;
  }
  return true;
}

bool ThrowCollocationNlp::get_starting_point(Ipopt::Index n, bool init_x, Ipopt::Number* x,
                                             bool init_z, Ipopt::Number*, Ipopt::Number*,
                                             Ipopt::Index, bool init_lambda, Ipopt::Number*) {
  if (!init_x || init_z || init_lambda) return false;
  Eigen::Map<Eigen::VectorXd>(x, n) = initialGuess();
  return true;
}

bool ThrowCollocationNlp::eval_f(Ipopt::Index, const Ipopt::Number* x, bool,
                                 Ipopt::Number& obj_value) {
  evaluatePoints(x);
  double sum = 0.0;
  for (int j = 0; j < pointCount(); ++j) sum += quadratureWeight(j) * values_[j](kCostOutput);
  obj_value = sum;
  return std::isfinite(sum);
}

bool ThrowCollocationNlp::eval_grad_f(Ipopt::Index n, const Ipopt::Number* x, bool,
                                      Ipopt::Number* grad_f) {
  evaluatePoints(x);
  std::fill(grad_f, grad_f + n, 0.0);
  for (int j = 0; j < pointCount(); ++j) {
    const double w = quadratureWeight(j);
    for (int d : output_deps_[kCostOutput]) grad_f[kP * j + d] = w * jacobians_[j](kCostOutput, d);
  }
  return true;
}

bool ThrowCollocationNlp::eval_g(Ipopt::Index, const Ipopt::Number* x, bool, Ipopt::Index,
                                 Ipopt::Number* g) {
  evaluatePoints(x);
  return constraintsFrom(x, values_, g);
}

bool ThrowCollocationNlp::constraintsFrom(const double* x, const std::vector<OutputVector>& values,
                                          double* g) const {
  for (int k = 0; k < intervals_; ++k) {
    const int a = 2 * k, m = 2 * k + 1, b = 2 * k + 2;
    const double h = intervalLength(k);
    for (int i = 0; i < kS; ++i) {
      const double s_a = x[kP * a + i], s_m = x[kP * m + i], s_b = x[kP * b + i];
      const double f_a = values[a](i), f_m = values[m](i), f_b = values[b](i);
      g[14 * k + i] = s_b - s_a - h / 6.0 * (f_a + 4.0 * f_m + f_b);
      g[14 * k + kS + i] = s_m - 0.5 * (s_a + s_b) - h / 8.0 * (f_a - f_b);
    }
  }
  for (int j = 1; j < pointCount() - 1; ++j) {
    g[14 * intervals_ + (j - 1)] = values[j](kNormalForceOutput);
  }
  for (int j = 0; j + 1 < pointCount(); ++j) {
    for (int i = 0; i < planar::kInputSize; ++i) {
      g[slewRow(j, i)] = x[kP * (j + 1) + kS + i] - x[kP * j + kS + i];
    }
  }
  for (int r = 0; r < constraintCount(); ++r) {
    if (!std::isfinite(g[r])) return false;
  }
  return true;
}

bool ThrowCollocationNlp::eval_jac_g(Ipopt::Index, const Ipopt::Number* x, bool, Ipopt::Index,
                                     Ipopt::Index nele_jac, Ipopt::Index* iRow,
                                     Ipopt::Index* jCol, Ipopt::Number* values) {
  if (values == nullptr) {
    std::copy(jac_rows_.begin(), jac_rows_.end(), iRow);
    std::copy(jac_cols_.begin(), jac_cols_.end(), jCol);
    return true;
  }
  evaluatePoints(x);
  std::fill(values, values + nele_jac, 0.0);
  std::size_t e = 0;
  forEachJacobianEntry(true, [&](int, int, double v) { values[jac_slot_[e++]] += v; });
  return true;
}

bool ThrowCollocationNlp::eval_h(Ipopt::Index, const Ipopt::Number* x, bool,
                                 Ipopt::Number obj_factor, Ipopt::Index,
                                 const Ipopt::Number* lambda, bool, Ipopt::Index,
                                 Ipopt::Index* iRow, Ipopt::Index* jCol,
                                 Ipopt::Number* values) {
  if (values == nullptr) {
    std::copy(hess_rows_.begin(), hess_rows_.end(), iRow);
    std::copy(hess_cols_.begin(), hess_cols_.end(), jCol);
    return true;
  }
  const int last = pointCount() - 1;
  std::size_t e = 0;
  for (int j = 0; j <= last; ++j) {
    // The weight of each point output in the Lagrangian (see the header's constraint rows).
    OutputVector w = OutputVector::Zero();
    for (int i = 0; i < kS; ++i) {
      if (j % 2 == 1) {
        const int k = (j - 1) / 2;
        w(i) = -4.0 * intervalLength(k) / 6.0 * lambda[14 * k + i];
      } else {
        const int k = j / 2;
        if (k < intervals_) {
          const double h = intervalLength(k);
          w(i) += -h / 6.0 * lambda[14 * k + i] - h / 8.0 * lambda[14 * k + kS + i];
        }
        if (k > 0) {
          const double h = intervalLength(k - 1);
          w(i) += -h / 6.0 * lambda[14 * (k - 1) + i] + h / 8.0 * lambda[14 * (k - 1) + kS + i];
        }
      }
    }
    if (j > 0 && j < last) w(kNormalForceOutput) = lambda[14 * intervals_ + (j - 1)];
    w(kCostOutput) = obj_factor * quadratureWeight(j);
    const PointVector p = Eigen::Map<const PointVector>(x + kP * j);
    const Eigen::Matrix<double, kP, kP> hess = pointHessian(p, w, problem_);
    for (const auto& [r, c] : hess_pattern_) values[e++] = hess(r, c);
  }
  return true;
}

void ThrowCollocationNlp::finalize_solution(Ipopt::SolverReturn, Ipopt::Index n,
                                            const Ipopt::Number* x, const Ipopt::Number*,
                                            const Ipopt::Number*, Ipopt::Index,
                                            const Ipopt::Number*, const Ipopt::Number*,
                                            Ipopt::Number obj_value, const Ipopt::IpoptData*,
                                            Ipopt::IpoptCalculatedQuantities*) {
  solution_ = Eigen::Map<const Eigen::VectorXd>(x, n);
  solution_objective_ = obj_value;
}

}  // namespace gs::planning
