// Problem (34) transcribed by Hermite-Simpson collocation (separated form) for IPOPT.
//
// Variables: 2N + 1 points p_j = (s_j, u_j) in R^9, j even the knots, j odd the interval
// midpoints. Per interval k with points a = 2k, m = 2k + 1, b = 2k + 2 and h = T / N:
//   Simpson defect   s_b - s_a - h/6 (f_a + 4 f_m + f_b)       = 0   (7 rows)
//   Hermite midpoint s_m - (s_a + s_b)/2 - h/8 (f_a - f_b)     = 0   (7 rows)
// then F_N(p_j) >= 0 at every point with free variables (j = 1 .. 2N-1; the end points are fixed
// and F_N there is g and, by the choice of a_q,T, exactly 0), then the input slew limits between
// consecutive points, |u_{j+1} - u_j| <= rate (t_{j+1} - t_j) (2 rows per pair, linear, in the
// inputs' units so that IPOPT's bound relaxation stays far below 1e-6; a rate of 0 is no bound). The objective is the Simpson
// quadrature of the running cost of (34). Boundary conditions are fixed variable bounds, which
// IPOPT removes from the problem.
//
// Every nonlinear term lives in the point function g(p) = (f(s, u), F_N(s, u), cost(s, u)) of
// one point, and the constraints are linear in the g's. So the Jacobian comes from one
// fixed-size forward AD pass per point (Eigen::AutoDiffScalar<Matrix<double, 9, 1>>), and the
// exact Hessian of the Lagrangian is block diagonal: per point, the Hessian of a weighted sum
// w_j . g(p_j) (weights collected from the multipliers), by nested forward AD. The sparsity
// patterns are read off AD derivatives at a few generic points when the NLP is built, so they
// follow the model rather than a hand-kept list.
#pragma once

#include <Eigen/Core>
#include <IpTNLP.hpp>
#include <vector>

#include "groundstation/planning/throw_problem.hpp"
#include "groundstation/planning/throw_trajectory.hpp"

namespace gs::planning {

// Knot times 0 = t_0 < ... < t_N = T. end_refinement r in [0, 1) shortens the intervals at both
// ends to (1 - r) T / N and lengthens the middle ones to (1 + r) T / N, smoothly (a sine map).
// The optimal throw's inputs change fastest at the fixed end inputs (hover at 0, the launch input
// at T, which the unconstrained optimum would jump to), so that is where resolution pays.
std::vector<double> throwCollocationMesh(double duration_s, int intervals, double end_refinement);

class ThrowCollocationNlp final : public Ipopt::TNLP {
 public:
  static constexpr int kPointSize = model::planar::kStateSize + model::planar::kInputSize;
  static constexpr int kOutputs = model::planar::kStateSize + 2;  // f, F_N, running cost
  static constexpr int kNormalForceOutput = model::planar::kStateSize;
  static constexpr int kCostOutput = model::planar::kStateSize + 1;

  // Precondition: problem.validate() is empty; knots_s strictly increasing from 0 to T, at least
  // two of them (throwCollocationMesh).
  ThrowCollocationNlp(const ThrowProblem& problem, std::vector<double> knots_s);

  int intervals() const { return intervals_; }
  int pointCount() const { return 2 * intervals_ + 1; }
  int variableCount() const { return kPointSize * pointCount(); }
  int constraintCount() const { return slewRow(pointCount() - 1, 0); }
  int jacobianNonzeros() const { return static_cast<int>(jac_rows_.size()); }
  int hessianNonzeros() const { return static_cast<int>(hess_rows_.size()); }

  // The straight line from hover to the launch state, states and inputs alike: the starting
  // point given to IPOPT.
  Eigen::VectorXd initialGuess() const;
  // The trajectory a variable vector describes (with F_N at every point).
  ThrowTrajectory trajectoryFrom(const Eigen::VectorXd& x) const;
  // The largest violation of any constraint or bound at x (dynamics defects, F_N >= 0, input
  // box, fixed end points): the figure to hold against the 1e-6 requirement.
  double maxViolation(const Eigen::VectorXd& x) const;

  // What IPOPT handed back in finalize_solution.
  const Eigen::VectorXd& solution() const { return solution_; }
  double solutionObjective() const { return solution_objective_; }

  // Ipopt::TNLP.
  bool get_nlp_info(Ipopt::Index& n, Ipopt::Index& m, Ipopt::Index& nnz_jac_g,
                    Ipopt::Index& nnz_h_lag, IndexStyleEnum& index_style) override;
  bool get_bounds_info(Ipopt::Index n, Ipopt::Number* x_l, Ipopt::Number* x_u, Ipopt::Index m,
                       Ipopt::Number* g_l, Ipopt::Number* g_u) override;
  bool get_starting_point(Ipopt::Index n, bool init_x, Ipopt::Number* x, bool init_z,
                          Ipopt::Number* z_L, Ipopt::Number* z_U, Ipopt::Index m,
                          bool init_lambda, Ipopt::Number* lambda) override;
  bool eval_f(Ipopt::Index n, const Ipopt::Number* x, bool new_x,
              Ipopt::Number& obj_value) override;
  bool eval_grad_f(Ipopt::Index n, const Ipopt::Number* x, bool new_x,
                   Ipopt::Number* grad_f) override;
  bool eval_g(Ipopt::Index n, const Ipopt::Number* x, bool new_x, Ipopt::Index m,
              Ipopt::Number* g) override;
  bool eval_jac_g(Ipopt::Index n, const Ipopt::Number* x, bool new_x, Ipopt::Index m,
                  Ipopt::Index nele_jac, Ipopt::Index* iRow, Ipopt::Index* jCol,
                  Ipopt::Number* values) override;
  bool eval_h(Ipopt::Index n, const Ipopt::Number* x, bool new_x, Ipopt::Number obj_factor,
              Ipopt::Index m, const Ipopt::Number* lambda, bool new_lambda,
              Ipopt::Index nele_hess, Ipopt::Index* iRow, Ipopt::Index* jCol,
              Ipopt::Number* values) override;
  void finalize_solution(Ipopt::SolverReturn status, Ipopt::Index n, const Ipopt::Number* x,
                         const Ipopt::Number* z_L, const Ipopt::Number* z_U, Ipopt::Index m,
                         const Ipopt::Number* g, const Ipopt::Number* lambda,
                         Ipopt::Number obj_value, const Ipopt::IpoptData* ip_data,
                         Ipopt::IpoptCalculatedQuantities* ip_cq) override;

 private:
  using PointVector = Eigen::Matrix<double, kPointSize, 1>;
  using OutputVector = Eigen::Matrix<double, kOutputs, 1>;
  using PointJacobian = Eigen::Matrix<double, kOutputs, kPointSize>;

  // Walks every Jacobian contribution in a fixed order: emit(row, col, value). With
  // `with_values` false the values are not computed (structure pass).
  template <typename Emit>
  void forEachJacobianEntry(bool with_values, Emit&& emit) const;
  void evaluatePoints(const double* x);
  bool constraintsFrom(const double* x, const std::vector<OutputVector>& values, double* g) const;
  double quadratureWeight(int point) const;
  double intervalLength(int k) const { return knots_s_[k + 1] - knots_s_[k]; }
  // The row of input i's slew between points j and j + 1.
  int slewRow(int j, int i) const { return 14 * intervals_ + (pointCount() - 2) + 2 * j + i; }
  double slewLimit(int row) const;  // the bound of a slew row; infinity when off
  double pointTime(int point) const;
  void fixedBounds(Eigen::VectorXd& lower, Eigen::VectorXd& upper) const;

  ThrowProblem problem_;
  int intervals_;
  std::vector<double> knots_s_;

  // Sparsity, read off the model.
  std::vector<std::vector<int>> output_deps_;  // per output, the point variables it depends on
  std::vector<std::pair<int, int>> hess_pattern_;  // (row >= col) within a point

  std::vector<int> jac_rows_, jac_cols_, jac_slot_;  // slot: emission -> nonzero index
  std::vector<int> hess_rows_, hess_cols_;

  // Cache of the point function at the last x.
  Eigen::VectorXd cached_x_;
  bool cache_valid_ = false;
  std::vector<OutputVector> values_;
  std::vector<PointJacobian> jacobians_;

  Eigen::VectorXd solution_;
  double solution_objective_ = 0.0;
};

}  // namespace gs::planning
