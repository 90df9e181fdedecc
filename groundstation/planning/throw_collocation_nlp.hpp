// Problem (34) transcribed by Hermite-Simpson collocation in its compressed form for IPOPT.
//
// Variables: per knot k = 0..N the point p_k = (s_k, u_k) in R^9 and four slacks (below).
// Between two knots a = k, b = k + 1 with h = t_b - t_a the input is linear, and the state is
// the cubic Hermite polynomial through the knot states and slopes f_a = f(p_a), f_b = f(p_b);
// its midpoint is
//   p_m(p_a, p_b) = ((s_a + s_b)/2 + h/8 (f_a - f_b), (u_a + u_b)/2).
// Rows, all equalities; the inequalities of (34) are bounds on the slacks:
//   interval k (10)  Simpson defect s_b - s_a - h/6 (f_a + 4 f(p_m) + f_b) = 0     (7)
//                    F_N(p_m) - sigma_m,k = 0,            sigma_m,k >= 0
//                    u_b - u_a - sigma_u,k = 0,           |sigma_u,k| <= rate h   (2, input slew)
//   inner knot j     F_N(p_j) - sigma_j = 0,              sigma_j >= 0
// The end knots are fixed (F_N is g at the start and, by the choice of a_q,T, exactly 0 at T)
// by variable bounds, which IPOPT removes from the problem, as it does the slacks without a row.
// The slews are in the inputs' units so that IPOPT's bound relaxation stays far below 1e-6; a
// rate of 0 is no bound; a linear input moves at most half as much to the midpoint. The
// objective is the Simpson quadrature of the running cost of (34). This is the separated scheme
// (midpoint states as variables, Hermite rows) with the midpoint input tied to the knots, in half
// the unknowns and rows.
//
// The slacks are ours rather than IPOPT's, and the Jacobian and Hessian blocks are declared dense
// (explicit zeros included: an interval's rows on its first knot with its slacks and on its
// second knot's point, a knot's row on the knot with its slacks), for the sake of MUMPS: the solve time is the
// KKT factorisations and solves, and those cost per node of MUMPS's elimination tree far more
// than per nonzero. Declared this way, a knot's variables and an interval's rows are each a
// few indistinguishable supervariables, so the tree has a few hundred nodes, not thousands.
//
// Every nonlinear term lives in the point function g(p) = (f(s, u), F_N(s, u), cost(s, u)),
// evaluated at the knots and, through p_m, at the midpoints. Its Jacobian comes from one
// fixed-size forward AD pass per point (Eigen::AutoDiffScalar<Matrix<double, 9, 1>>) and the
// chain rule through p_m; the exact Hessian of the Lagrangian from per-point Hessians of weighted
// sums w . g(p) (nested forward AD) assembled the same way.
//
// A throw to a target (ThrowProblem::catch_target) frees the end knot (its inputs stay in the
// box) and appends one variable, the catching instant t_c after the release, and four rows:
//   F_N(p_N) = 0                                   the pole leaves the plate at T (Section III-A)
//   catch_target_residuals(s_N, t_c) = 0           the lower end on the target at the instant
//                                                  where (42) holds (throw_problem.hpp)
// F_N's curvature joins knot N's point Hessian; the catch rows' Hessian, from nested forward AD
// through the pole's RK4 flight, is dense in (v_x, v_z, alpha, alpha', t_c), and the structure
// gains t_c's row: its coupling to knot N's point and its diagonal.
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
std::vector<double> throw_collocation_mesh(double duration_s, int intervals, double end_refinement);

class ThrowCollocationNlp final : public Ipopt::TNLP {
 public:
  static constexpr int kPointSize = model::planar::kStateSize + model::planar::kInputSize;
  static constexpr int kKnotSize = kPointSize + 4;  // the point and its four slacks
  static constexpr int kIntervalRows = model::planar::kStateSize + 3;
  static constexpr int kOutputs = model::planar::kStateSize + 2;  // f, F_N, running cost
  static constexpr int kNormalForceOutput = model::planar::kStateSize;
  static constexpr int kCostOutput = model::planar::kStateSize + 1;
  static constexpr int kTerminalRows = 4;  // F_N(p_N) and the three catch residuals

  // Precondition: problem.validate() is empty; knots_s strictly increasing from 0 to T, at least
  // two of them (throw_collocation_mesh). Throws std::logic_error if the model has become curved
  // in variables the point Hessians leave out (x, z, vx, vz; see the implementation).
  ThrowCollocationNlp(const ThrowProblem& problem, std::vector<double> knots_s);

  int intervals() const { return intervals_; }
  int knot_count() const { return intervals_ + 1; }
  // Collocation points of the trajectory: the knots and the interval midpoints, in time order.
  int point_count() const { return 2 * intervals_ + 1; }
  bool has_target() const { return problem_.catch_target.has_value(); }
  int variable_count() const { return kKnotSize * knot_count() + (has_target() ? 1 : 0); }
  int constraint_count() const { return knot_row(intervals_) + (has_target() ? kTerminalRows : 0); }
  // The index of t_c among the variables (target throws only).
  int catch_time_variable() const { return kKnotSize * knot_count(); }
  int jacobian_nonzeros() const { return static_cast<int>(jac_rows_.size()); }
  int hessian_nonzeros() const { return static_cast<int>(hess_rows_.size()); }

  // The starting point given to IPOPT: the warm start if one is set, else the straight line from
  // hover to the launch state, states and inputs alike (t_c from catch_time_guess_s); each slack
  // at its row's value moved into its bounds.
  Eigen::VectorXd initial_guess() const;
  // Start from `trajectory` (interpolated at the knots; any mesh over the same duration) with
  // catching instant catch_time_s (ignored without a target).
  void set_warm_start(const ThrowTrajectory& trajectory, double catch_time_s);
  // The trajectory a variable vector describes (with F_N at every point).
  ThrowTrajectory trajectory_from(const Eigen::VectorXd& x) const;
  // The largest violation of any constraint or bound at x (dynamics defects, F_N >= 0, input
  // box, fixed end points; for a target throw F_N = 0 at T, the catch rows and t_c's bounds): the
  // figure to hold against the 1e-6 requirement.
  double max_violation(const Eigen::VectorXd& x) const;

  // What IPOPT handed back in finalize_solution.
  const Eigen::VectorXd& solution() const { return solution_; }
  double solution_objective() const { return solution_objective_; }

  // Ipopt::TNLP.
  bool get_nlp_info(Ipopt::Index& n, Ipopt::Index& m, Ipopt::Index& nnz_jac_g, Ipopt::Index& nnz_h_lag,
                    IndexStyleEnum& index_style) override;
  bool get_bounds_info(Ipopt::Index n, Ipopt::Number* x_l, Ipopt::Number* x_u, Ipopt::Index m,
                       Ipopt::Number* g_l, Ipopt::Number* g_u) override;
  bool get_starting_point(Ipopt::Index n, bool init_x, Ipopt::Number* x, bool init_z, Ipopt::Number* z_L,
                          Ipopt::Number* z_U, Ipopt::Index m, bool init_lambda,
                          Ipopt::Number* lambda) override;
  bool eval_f(Ipopt::Index n, const Ipopt::Number* x, bool new_x, Ipopt::Number& obj_value) override;
  bool eval_grad_f(Ipopt::Index n, const Ipopt::Number* x, bool new_x, Ipopt::Number* grad_f) override;
  bool eval_g(Ipopt::Index n, const Ipopt::Number* x, bool new_x, Ipopt::Index m, Ipopt::Number* g) override;
  bool eval_jac_g(Ipopt::Index n, const Ipopt::Number* x, bool new_x, Ipopt::Index m, Ipopt::Index nele_jac,
                  Ipopt::Index* iRow, Ipopt::Index* jCol, Ipopt::Number* values) override;
  bool eval_h(Ipopt::Index n, const Ipopt::Number* x, bool new_x, Ipopt::Number obj_factor, Ipopt::Index m,
              const Ipopt::Number* lambda, bool new_lambda, Ipopt::Index nele_hess, Ipopt::Index* iRow,
              Ipopt::Index* jCol, Ipopt::Number* values) override;
  void finalize_solution(Ipopt::SolverReturn status, Ipopt::Index n, const Ipopt::Number* x,
                         const Ipopt::Number* z_L, const Ipopt::Number* z_U, Ipopt::Index m,
                         const Ipopt::Number* g, const Ipopt::Number* lambda, Ipopt::Number obj_value,
                         const Ipopt::IpoptData* ip_data, Ipopt::IpoptCalculatedQuantities* ip_cq) override;

 private:
  using PointVector = Eigen::Matrix<double, kPointSize, 1>;
  using OutputVector = Eigen::Matrix<double, kOutputs, 1>;
  using PointJacobian = Eigen::Matrix<double, kOutputs, kPointSize>;
  using PairVector = Eigen::Matrix<double, 2 * kPointSize, 1>;            // (p_a, p_b) of an interval
  using MidpointMap = Eigen::Matrix<double, kPointSize, 2 * kPointSize>;  // d p_m / d(p_a, p_b)
  using PairJacobian = Eigen::Matrix<double, kOutputs, 2 * kPointSize>;
  using SimpsonJacobian = Eigen::Matrix<double, model::planar::kStateSize, 2 * kPointSize>;
  using Block = Eigen::Matrix<double, kPointSize, kPointSize>;
  // The terminal variables q = (p_N, t_c) and the catch rows' derivatives in them.
  using TerminalVector = Eigen::Matrix<double, kPointSize + 1, 1>;
  using CatchJacobian = Eigen::Matrix<double, 3, kPointSize + 1>;

  // The point function at every knot and midpoint of x, with its derivatives.
  struct Evaluation {
    std::vector<OutputVector> knot_value, mid_value;
    std::vector<PointJacobian> knot_jacobian, mid_jacobian;  // d g / d p at the point
    std::vector<PointVector> mid_point;                      // p_m
    std::vector<MidpointMap> mid_map;                        // d p_m / d(p_a, p_b)
    std::vector<PairJacobian> mid_total;                     // d g(p_m) / d(p_a, p_b)
    Eigen::Vector3d catch_value = Eigen::Vector3d::Zero();   // target throws: the catch rows
    CatchJacobian catch_jacobian = CatchJacobian::Zero();    // and d / d(p_N, t_c)
  };
  void evaluate(const double* x, Evaluation& e) const;
  void evaluate_cached(const double* x);
  TerminalVector terminal_vector(
      const double* x) const;  // (p_N, t_c)  // into cache_, unless x is the cached point
  bool constraints_from(const double* x, const Evaluation& e, double* g) const;
  SimpsonJacobian simpson_jacobian(int k, const Evaluation& e) const;  // interval k's 7 rows
  // The Lagrangian's Hessian as blocks: per knot, and between knots k + 1 (rows) and k.
  void hessian_blocks(const double* x, const Evaluation& e, double obj_factor, const double* lambda,
                      std::vector<Block>& diagonal, std::vector<Block>& coupling) const;
  double interval_length(int k) const { return knots_s_[k + 1] - knots_s_[k]; }
  int knot_row(int j) const { return kIntervalRows * intervals_ + j - 1; }  // F_N at knot 1..N-1
  double slew_limit(int k, int i) const;  // |bound| of interval k's input-i slew; infinity when off
  double point_time(int point) const;
  void fixed_bounds(Eigen::VectorXd& lower, Eigen::VectorXd& upper) const;

  ThrowProblem problem_;
  int intervals_;
  std::vector<double> knots_s_;

  std::vector<int> jac_rows_, jac_cols_;  // in the order eval_jac_g writes the values
  std::vector<int> hess_rows_, hess_cols_;
  std::vector<Block> hess_diagonal_, hess_coupling_;                     // eval_h's workspace
  Eigen::Matrix<double, kPointSize + 1, kPointSize + 1> hess_terminal_;  // catch rows, in (p_N, t_c)

  Eigen::VectorXd warm_start_;  // empty: the straight line

  Eigen::VectorXd cached_x_;
  bool cache_valid_ = false;
  Evaluation cache_;

  Eigen::VectorXd solution_;
  double solution_objective_ = 0.0;
};

}  // namespace gs::planning
