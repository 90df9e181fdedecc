// Infinite-horizon LQR: u = u0 - K (x - x0) minimising int x^T Q x + u^T R u dt for x' = A x + B u.
#pragma once

#include <Eigen/Core>

#include "groundstation/control/linear_system.hpp"

namespace gs::control {

struct LqrGain {
  Eigen::MatrixXd K;                         // m x n
  Eigen::MatrixXd P;                         // n x n cost-to-go
  Eigen::VectorXcd closed_loop_eigenvalues;  // of A - B K
  bool ok = false;                           // CARE converged and A - B K Hurwitz
  double care_residual = 0.0;                // relative (riccati.hpp)
};

LqrGain solve_lqr(const LinearSystem& sys, const Eigen::MatrixXd& Q, const Eigen::MatrixXd& R);

// Diagonal weights, the form every design in this folder uses.
struct LqrWeights {
  Eigen::VectorXd state;  // diag(Q)
  Eigen::VectorXd input;  // diag(R)
};
LqrGain solve_lqr(const LinearSystem& sys, const LqrWeights& weights);

}  // namespace gs::control
