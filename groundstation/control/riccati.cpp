#include "groundstation/control/riccati.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/QR>
#include <cmath>

#include "groundstation/control/lyapunov.hpp"

namespace gs::control {

namespace {

// B R^-1 B^T via the Cholesky factor of R.
Eigen::MatrixXd input_weight(const Eigen::MatrixXd& B, const Eigen::MatrixXd& R) {
  return B * R.llt().solve(B.transpose());
}

// Res(P) and its size relative to the terms that cancel in it.
struct Residual {
  Eigen::MatrixXd value;
  double relative;
};
Residual residual(const Eigen::MatrixXd& A, const Eigen::MatrixXd& S, const Eigen::MatrixXd& Q,
                  const Eigen::MatrixXd& P) {
  const Eigen::MatrixXd AtP = A.transpose() * P;
  const Eigen::MatrixXd PSP = P * S * P;
  Residual r{AtP + AtP.transpose() - PSP + Q, 0.0};
  const double scale = 2.0 * AtP.norm() + PSP.norm() + Q.norm();
  r.relative = r.value.norm() / std::max(scale, 1e-300);
  return r;
}

bool is_hurwitz(const Eigen::MatrixXd& M) {
  if (!M.allFinite()) return false;
  const Eigen::VectorXcd eig = M.eigenvalues();
  for (Eigen::Index i = 0; i < eig.size(); ++i) {
    if (!(eig(i).real() < 0.0)) return false;
  }
  return true;
}

}  // namespace

Eigen::MatrixXd care_residual(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& Q,
                              const Eigen::MatrixXd& R, const Eigen::MatrixXd& P) {
  const Eigen::MatrixXd S = input_weight(B, R);
  return A.transpose() * P + P * A - P * S * P + Q;
}

CareSolution solve_care(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& Q,
                        const Eigen::MatrixXd& R, const CareOptions& options) {
  CareSolution out;
  const Eigen::Index n = A.rows();
  const Eigen::Index m = B.cols();
  if (A.cols() != n || B.rows() != n || Q.rows() != n || Q.cols() != n || R.rows() != m || R.cols() != m ||
      !A.allFinite() || !B.allFinite() || !Q.allFinite() || !R.allFinite()) {
    return out;
  }
  Eigen::LLT<Eigen::MatrixXd> r_llt(R);
  if (r_llt.info() != Eigen::Success) return out;
  const Eigen::MatrixXd S = B * r_llt.solve(B.transpose());
  const Eigen::MatrixXd Qs = 0.5 * (Q + Q.transpose());

  // Hamiltonian and its sign.
  const Eigen::Index N = 2 * n;
  Eigen::MatrixXd Z(N, N);
  Z << A, -S, -Qs, -A.transpose();
  bool sign_converged = false;
  for (int it = 0; it < options.max_sign_iterations; ++it) {
    Eigen::PartialPivLU<Eigen::MatrixXd> lu(Z);
    const Eigen::VectorXd diag = lu.matrixLU().diagonal().cwiseAbs();
    if (!(diag.minCoeff() > 0.0) || !diag.allFinite()) break;  // eigenvalue at 0: not solvable
    const double log_det = diag.array().log().sum();
    const double mu = std::exp(-log_det / static_cast<double>(N));
    const Eigen::MatrixXd Z_next = 0.5 * (mu * Z + lu.inverse() / mu);
    const double change = (Z_next - Z).cwiseAbs().colwise().sum().maxCoeff();
    const double size = Z_next.cwiseAbs().colwise().sum().maxCoeff();
    Z = Z_next;
    out.sign_iterations = it + 1;
    if (!Z.allFinite()) break;
    if (change <= options.sign_tolerance * size) {
      sign_converged = true;
      break;
    }
  }
  if (!sign_converged) return out;

  Eigen::MatrixXd lhs(N, n), rhs(N, n);
  lhs << Z.topRightCorner(n, n), Z.bottomRightCorner(n, n) + Eigen::MatrixXd::Identity(n, n);
  rhs << Z.topLeftCorner(n, n) + Eigen::MatrixXd::Identity(n, n), Z.bottomLeftCorner(n, n);
  Eigen::MatrixXd P = lhs.colPivHouseholderQr().solve(-rhs);
  P = 0.5 * (P + P.transpose()).eval();

  // Newton-Kleinman refinement in residual form.
  Residual res = residual(A, S, Qs, P);
  for (int step = 0; step < options.max_newton_steps && res.relative > 1e-15; ++step) {
    const Eigen::MatrixXd Ac = A - S * P;
    const auto dP = solve_continuous_lyapunov(Ac, res.value);
    if (!dP) break;
    Eigen::MatrixXd P_next = P + *dP;
    P_next = 0.5 * (P_next + P_next.transpose()).eval();
    Residual res_next = residual(A, S, Qs, P_next);
    if (!(res_next.relative < res.relative)) break;
    P = std::move(P_next);
    res = std::move(res_next);
    out.newton_steps = step + 1;
  }

  out.P = P;
  out.K = r_llt.solve(B.transpose() * P);
  out.residual = res.relative;
  out.converged = is_hurwitz(A - B * out.K);
  return out;
}

}  // namespace gs::control
