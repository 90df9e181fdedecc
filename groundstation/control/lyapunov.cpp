#include "groundstation/control/lyapunov.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <complex>

namespace gs::control {

std::optional<Eigen::MatrixXd> solve_continuous_lyapunov(const Eigen::MatrixXd& A, const Eigen::MatrixXd& C) {
  const Eigen::Index n = A.rows();
  if (A.cols() != n || C.rows() != n || C.cols() != n) return std::nullopt;
  if (!A.allFinite() || !C.allFinite()) return std::nullopt;
  if (n == 0) return Eigen::MatrixXd(0, 0);

  Eigen::ComplexSchur<Eigen::MatrixXd> schur(A);
  if (schur.info() != Eigen::Success) return std::nullopt;
  const Eigen::MatrixXcd& T = schur.matrixT();
  const Eigen::MatrixXcd& U = schur.matrixU();
  const Eigen::MatrixXcd Ct = -(U.adjoint() * C.cast<std::complex<double>>() * U);

  // T^H Y + Y T = Ct:  Y_ij (conj(T_ii) + T_jj) = Ct_ij - sum_{k<i} conj(T_ki) Y_kj
  //                                                     - sum_{k<j} Y_ik T_kj.
  const double scale = std::max(1.0, T.cwiseAbs().maxCoeff());
  Eigen::MatrixXcd Y(n, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index j = 0; j < n; ++j) {
      std::complex<double> rhs = Ct(i, j);
      for (Eigen::Index k = 0; k < i; ++k) rhs -= std::conj(T(k, i)) * Y(k, j);
      for (Eigen::Index k = 0; k < j; ++k) rhs -= Y(i, k) * T(k, j);
      const std::complex<double> denom = std::conj(T(i, i)) + T(j, j);
      if (std::abs(denom) <= 1e-14 * scale) return std::nullopt;
      Y(i, j) = rhs / denom;
    }
  }
  Eigen::MatrixXd X = (U * Y * U.adjoint()).real();
  if (C.isApprox(C.transpose(), 1e-12)) X = 0.5 * (X + X.transpose()).eval();
  if (!X.allFinite()) return std::nullopt;
  return X;
}

}  // namespace gs::control
