#include "groundstation/control/lqr.hpp"

#include <Eigen/Eigenvalues>

#include "groundstation/control/riccati.hpp"

namespace gs::control {

LqrGain solve_lqr(const LinearSystem& sys, const Eigen::MatrixXd& Q, const Eigen::MatrixXd& R) {
  LqrGain out;
  const CareSolution care = solve_care(sys.A, sys.B, Q, R);
  if (care.P.size() == 0) return out;
  out.K = care.K;
  out.P = care.P;
  out.care_residual = care.residual;
  out.closed_loop_eigenvalues = (sys.A - sys.B * care.K).eigenvalues();
  out.ok = care.converged;
  return out;
}

LqrGain solve_lqr(const LinearSystem& sys, const LqrWeights& weights) {
  return solve_lqr(sys, Eigen::MatrixXd(weights.state.asDiagonal()),
                   Eigen::MatrixXd(weights.input.asDiagonal()));
}

}  // namespace gs::control
