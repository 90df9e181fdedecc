// The continuous-time algebraic Riccati equation (CARE) of the infinite-horizon LQR:
//   A^T P + P A - P B R^-1 B^T P + Q = 0,  K = R^-1 B^T P,  A - B K Hurwitz.
//
// Method. The stabilising solution spans the stable invariant subspace of the Hamiltonian
//   H = [A, -B R^-1 B^T; -Q, -A^T]:  H [I; P] = [I; P] (A - B K).
// We compute that subspace with the matrix sign function (Roberts 1971, Byers 1987): the
// Newton iteration Z <- (mu Z + (mu Z)^-1) / 2 with determinant scaling mu = |det Z|^(-1/2n)
// converges quadratically to W = sign(H), and sign(H) [I; P] = -[I; P] gives the overdetermined,
// consistent system [W12; W22 + I] P = -[W11 + I; W21], solved by QR. It needs no stabilising
// initial gain and no ordered Schur form (which Eigen lacks). Its accuracy is limited by the
// conditioning of the inversions, so the result is refined by Newton-Kleinman steps
// (Kleinman 1968) written in residual form: with A_c = A - B K,
//   A_c^T dP + dP A_c = -Res(P),  P <- P + dP,
// each solved by Bartels-Stewart (lyapunov.hpp), until the residual stops decreasing.
//
// Preconditions: (A, B) stabilisable, (Q^1/2, A) detectable, Q symmetric PSD, R symmetric PD.
// When they fail, H has eigenvalues on the imaginary axis, the sign iteration does not converge,
// and the result reports converged = false.
#pragma once

#include <Eigen/Core>

namespace gs::control {

struct CareOptions {
  int max_sign_iterations = 100;
  double sign_tolerance = 1e-13;  // relative change of Z in the 1-norm
  int max_newton_steps = 4;
};

struct CareSolution {
  Eigen::MatrixXd P;       // symmetric, positive semidefinite
  Eigen::MatrixXd K;       // R^-1 B^T P
  bool converged = false;  // sign iteration converged and A - B K is Hurwitz
  double residual = 0.0;   // ||Res(P)||_F / (2 ||A^T P||_F + ||P B R^-1 B^T P||_F + ||Q||_F)
  int sign_iterations = 0;
  int newton_steps = 0;
};

CareSolution solve_care(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& Q,
                        const Eigen::MatrixXd& R, const CareOptions& options = {});

// Res(P) = A^T P + P A - P B R^-1 B^T P + Q.
Eigen::MatrixXd care_residual(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& Q,
                              const Eigen::MatrixXd& R, const Eigen::MatrixXd& P);

}  // namespace gs::control
