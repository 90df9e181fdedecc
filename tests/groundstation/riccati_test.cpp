// The Lyapunov and algebraic Riccati solvers: residuals on random systems, a scalar case in closed
// form, the stabilising property, and the failure report when no stabilising solution exists.
#include "groundstation/control/riccati.hpp"

#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "groundstation/control/lyapunov.hpp"

namespace {

using gs::control::solve_care;
using gs::control::solve_continuous_lyapunov;

Eigen::MatrixXd random_matrix(std::mt19937& rng, int rows, int cols, double scale = 1.0) {
  std::normal_distribution<double> d(0.0, scale);
  Eigen::MatrixXd m(rows, cols);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) m(i, j) = d(rng);
  return m;
}

bool hurwitz(const Eigen::MatrixXd& M) { return (M.eigenvalues().real().array() < 0.0).all(); }

}  // namespace

TEST_CASE("Lyapunov: A^T X + X A + C = 0 on random stable and unstable matrices") {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 20; ++trial) {
    const int n = 2 + trial % 9;
    Eigen::MatrixXd A = random_matrix(rng, n, n);
    if (trial % 2 == 0) {
      // Make it Hurwitz by a shift.
      const double shift = A.eigenvalues().real().maxCoeff() + 0.5;
      A -= shift * Eigen::MatrixXd::Identity(n, n);
    }
    const Eigen::MatrixXd F = random_matrix(rng, n, n);
    const Eigen::MatrixXd C = F * F.transpose();
    const auto X = solve_continuous_lyapunov(A, C);
    REQUIRE(X);
    const Eigen::MatrixXd res = A.transpose() * *X + *X * A + C;
    CHECK(res.norm() / (C.norm() + 2 * A.norm() * X->norm()) < 1e-12);
    if (trial % 2 == 0) {
      // Hurwitz A and C > 0: X > 0.
      CHECK(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(*X).eigenvalues().minCoeff() > 0.0);
    }
  }
  // Eigenvalues summing to zero: no unique solution.
  Eigen::MatrixXd A(2, 2);
  A << 1, 0, 0, -1;
  CHECK_FALSE(solve_continuous_lyapunov(A, Eigen::MatrixXd::Identity(2, 2)));
}

TEST_CASE("CARE: the scalar case in closed form") {
  // a p + p a - p^2 b^2 / r + q = 0  =>  p = r (a + sqrt(a^2 + b^2 q / r)) / b^2.
  for (double a : {-2.0, 0.0, 1.0, 3.0}) {
    const double b = 0.7, q = 2.0, r = 0.5;
    const auto s = solve_care(Eigen::MatrixXd::Constant(1, 1, a), Eigen::MatrixXd::Constant(1, 1, b),
                              Eigen::MatrixXd::Constant(1, 1, q), Eigen::MatrixXd::Constant(1, 1, r));
    REQUIRE(s.converged);
    const double p = r * (a + std::sqrt(a * a + b * b * q / r)) / (b * b);
    CHECK(s.P(0, 0) == Approx(p).epsilon(1e-12));
    CHECK(s.K(0, 0) == Approx(b * p / r).epsilon(1e-12));
  }
  // The textbook case a = b = q = r = 1: p = 1 + sqrt(2).
  const auto one = Eigen::MatrixXd::Ones(1, 1);
  CHECK(solve_care(one, one, one, one).P(0, 0) == Approx(1.0 + std::sqrt(2.0)).epsilon(1e-14));
}

TEST_CASE("CARE: residual and stabilising solution on random stabilisable systems") {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 40; ++trial) {
    const int n = 2 + trial % 12;
    const int m = 1 + trial % 4;
    const Eigen::MatrixXd A = random_matrix(rng, n, n, 1.0 + (trial % 3));
    const Eigen::MatrixXd B = random_matrix(rng, n, m);
    const Eigen::MatrixXd C = random_matrix(rng, n, n);
    const Eigen::MatrixXd Q = C.transpose() * C + 1e-3 * Eigen::MatrixXd::Identity(n, n);
    const Eigen::MatrixXd F = random_matrix(rng, m, m);
    const Eigen::MatrixXd R = F * F.transpose() + 0.1 * Eigen::MatrixXd::Identity(m, m);
    const auto s = solve_care(A, B, Q, R);
    CAPTURE(trial, n, m, s.sign_iterations, s.newton_steps, s.residual, s.P.norm());
    REQUIRE(s.converged);
    // The residual against the size of the terms that cancel in it.
    const Eigen::MatrixXd res = gs::control::care_residual(A, B, Q, R, s.P);
    const Eigen::MatrixXd S = B * R.llt().solve(B.transpose());
    const double terms = (A.transpose() * s.P).norm() + (s.P * A).norm() + (s.P * S * s.P).norm() + Q.norm();
    CHECK(res.norm() / terms < 1e-9);
    CHECK(s.residual == Approx(res.norm() / terms).epsilon(1e-6).margin(1e-16));
    // Well-conditioned problems (moderate P) reach rounding level.
    if (s.P.norm() < 1e3) CHECK(s.residual < 1e-13);
    CHECK((s.P - s.P.transpose()).norm() == 0.0);
    CHECK(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(s.P).eigenvalues().minCoeff() > 0.0);
    CHECK(hurwitz(A - B * s.K));
    CHECK((s.K - R.llt().solve(B.transpose() * s.P)).norm() < 1e-9 * std::max(1.0, s.K.norm()));
  }
}

TEST_CASE("CARE: the LQR cost of the solution is the cost-to-go of the closed loop") {
  // For u = -K x, J(x0) = x0^T X x0 with (A - BK)^T X + X (A - BK) + Q + K^T R K = 0; at the
  // optimum X = P. A perturbed gain must cost more.
  std::mt19937 rng(5);
  const int n = 5, m = 2;
  const Eigen::MatrixXd A = random_matrix(rng, n, n);
  const Eigen::MatrixXd B = random_matrix(rng, n, m);
  const Eigen::MatrixXd Q = Eigen::MatrixXd::Identity(n, n);
  const Eigen::MatrixXd R = Eigen::MatrixXd::Identity(m, m);
  const auto s = solve_care(A, B, Q, R);
  REQUIRE(s.converged);
  auto cost = [&](const Eigen::MatrixXd& K) {
    return *solve_continuous_lyapunov(A - B * K, Q + K.transpose() * R * K);
  };
  CHECK((cost(s.K) - s.P).norm() < 1e-9 * s.P.norm());
  const Eigen::MatrixXd K2 = s.K + 0.05 * random_matrix(rng, m, n);
  REQUIRE(hurwitz(A - B * K2));
  CHECK((cost(K2) - s.P).trace() > 0.0);
}

TEST_CASE("CARE: an unstabilisable system is reported, not returned as a solution") {
  // An unstable mode the input cannot reach.
  Eigen::MatrixXd A(2, 2), B(2, 1);
  A << 1, 0, 0, -1;
  B << 0, 1;
  const auto s = solve_care(A, B, Eigen::MatrixXd::Identity(2, 2), Eigen::MatrixXd::Identity(1, 1));
  CHECK_FALSE(s.converged);
  // Non-finite input.
  Eigen::MatrixXd An = A;
  An(0, 0) = std::nan("");
  CHECK_FALSE(solve_care(An, B, Eigen::MatrixXd::Identity(2, 2), Eigen::MatrixXd::Identity(1, 1)).converged);
}
