// A linear(ised) system x' = A x + B u and the central-difference Jacobians of a nonlinear one,
// the bridge between the models (groundstation/model) and the LQR designs.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

namespace gs::control {

struct LinearSystem {
  Eigen::MatrixXd A;
  Eigen::MatrixXd B;
};

// Jacobians of f(x, u) at (x0, u0) by central differences with a per-coordinate step
// step * max(1, |coordinate|); truncation error O(step^2), so 1e-6 gives about 1e-10 for smooth
// f of unit scale. f: (const Eigen::VectorXd&, const Eigen::VectorXd&) -> Eigen::VectorXd.
template <typename Dynamics>
LinearSystem linearise(const Dynamics& f, const Eigen::VectorXd& x0, const Eigen::VectorXd& u0,
                       double step = 1e-6) {
  const Eigen::Index n = x0.size(), m = u0.size();
  LinearSystem sys{Eigen::MatrixXd(n, n), Eigen::MatrixXd(n, m)};
  for (Eigen::Index i = 0; i < n; ++i) {
    const double h = step * std::max(1.0, std::abs(x0(i)));
    Eigen::VectorXd xp = x0, xm = x0;
    xp(i) += h;
    xm(i) -= h;
    sys.A.col(i) = (f(xp, u0) - f(xm, u0)) / (2.0 * h);
  }
  for (Eigen::Index j = 0; j < m; ++j) {
    const double h = step * std::max(1.0, std::abs(u0(j)));
    Eigen::VectorXd up = u0, um = u0;
    up(j) += h;
    um(j) -= h;
    sys.B.col(j) = (f(x0, up) - f(x0, um)) / (2.0 * h);
  }
  return sys;
}

}  // namespace gs::control
