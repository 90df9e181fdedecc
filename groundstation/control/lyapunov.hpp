// Continuous-time Lyapunov equation A^T X + X A + C = 0, used by the Newton-Kleinman refinement
// of the Riccati solver (riccati.hpp) and by anyone who needs a closed-loop cost matrix.
#pragma once

#include <Eigen/Core>
#include <optional>

namespace gs::control {

// Bartels-Stewart with the complex Schur form A = U T U^H (no 2x2 blocks to handle): the equation
// becomes T^H Y + Y T = -U^H C U with Y = U^H X U, solved entry by entry in O(n^3) because T^H is
// lower and T upper triangular. Unique when no two eigenvalues of A satisfy conj(l_i) + l_j = 0
// (always true for a Hurwitz A); std::nullopt otherwise or for non-finite input. For a symmetric C
// the result is symmetrised.
std::optional<Eigen::MatrixXd> solve_continuous_lyapunov(const Eigen::MatrixXd& A, const Eigen::MatrixXd& C);

}  // namespace gs::control
