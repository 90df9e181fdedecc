// The finite-horizon time-varying LQR: convergence to the CARE on a long horizon, stationarity at
// P(tf) = P_care, a time-varying scalar case against its closed-form solution, the interpolation.
#include "groundstation/control/tvlqr.hpp"

#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <cmath>

#include "groundstation/control/balancing_lqr.hpp"
#include "groundstation/control/riccati.hpp"

namespace {

using gs::control::LinearSystem;
using gs::control::solve_tv_lqr;

}  // namespace

TEST_CASE("TV-LQR on a time-invariant system converges to the CARE solution") {
  // The balancing design (13 states, unstable open loop).
  const LinearSystem sys = gs::control::balancing_linearisation();
  const auto w = gs::control::balancing_lqr_weights();
  const Eigen::MatrixXd Q = w.state.asDiagonal();
  const Eigen::MatrixXd R = w.input.asDiagonal();
  const auto care = gs::control::solve_care(sys.A, sys.B, Q, R);
  REQUIRE(care.converged);

  const auto gains =
      solve_tv_lqr([&](double) { return sys; }, Q, R, Eigen::MatrixXd::Zero(Q.rows(), Q.cols()), 0.0, 20.0);
  REQUIRE_FALSE(gains.empty());
  CHECK(gains.times_s().front() == 0.0);
  CHECK(gains.times_s().back() == 20.0);
  CHECK((gains.cost(0.0) - care.P).norm() < 1e-6 * care.P.norm());
  CHECK((gains.gain(0.0) - care.K).norm() < 1e-6 * care.K.norm());
  // Near the end the terminal cost (zero) dominates: the gain fades.
  CHECK(gains.gain(20.0).norm() == Approx(0.0).margin(1e-12));
  CHECK(gains.gain(19.9).norm() < care.K.norm());

  // Starting at the stationary solution, P stays there.
  const auto stationary = solve_tv_lqr([&](double) { return sys; }, Q, R, care.P, 0.0, 2.0);
  REQUIRE_FALSE(stationary.empty());
  for (double t : {0.0, 0.5, 1.234, 2.0}) {
    CHECK((stationary.cost(t) - care.P).norm() < 1e-9 * care.P.norm());
  }
}

TEST_CASE("TV-LQR: time-varying scalar case against the closed-form Riccati solution") {
  // x' = a(t) x + u, a(t) = sin t, q = 0, r: with y = 1/p the Riccati equation
  // -p' = 2 a p - p^2 / r becomes the linear y' = 2 a(t) y - 1/r, so
  // y(t) = e^{2 A(t)} ( y(tf) e^{-2 A(tf)} + (1/r) int_t^tf e^{-2 A(s)} ds ),  A(t) = -cos t.
  const double r = 0.5, pf = 3.0, tf = 4.0;
  auto A = [](double t) { return -std::cos(t); };
  auto exact = [&](double t) {
    const int n = 4000;  // Simpson
    const double h = (tf - t) / n;
    double integral = 0.0;
    for (int i = 0; i <= n; ++i) {
      const double s = t + i * h;
      const double wgt = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
      integral += wgt * std::exp(-2.0 * A(s));
    }
    integral *= h / 3.0;
    const double y = std::exp(2.0 * A(t)) * (std::exp(-2.0 * A(tf)) / pf + integral / r);
    return 1.0 / y;
  };
  auto lin = [](double t) {
    return LinearSystem{Eigen::MatrixXd::Constant(1, 1, std::sin(t)), Eigen::MatrixXd::Ones(1, 1)};
  };
  const auto gains = solve_tv_lqr(lin, Eigen::MatrixXd::Zero(1, 1), Eigen::MatrixXd::Constant(1, 1, r),
                                  Eigen::MatrixXd::Constant(1, 1, pf), 0.0, tf, {0.01, 0.001});
  REQUIRE_FALSE(gains.empty());
  for (double t : {0.0, 0.5, 1.0, 2.0, 3.0, 3.9, 4.0}) {
    CAPTURE(t);
    CHECK(gains.cost(t)(0, 0) == Approx(exact(t)).epsilon(1e-9));
    CHECK(gains.gain(t)(0, 0) == Approx(exact(t) / r).epsilon(1e-9));
  }
  // Between grid points the gain is interpolated linearly (second-order accurate).
  CHECK(gains.cost(1.005)(0, 0) == Approx(exact(1.005)).epsilon(1e-4));
}

TEST_CASE("TV-LQR: sampled linearisations are interpolated, bad input gives no gains") {
  std::vector<double> times = {0.0, 1.0, 2.0};
  std::vector<LinearSystem> samples = {
      {Eigen::MatrixXd::Constant(1, 1, 0.0), Eigen::MatrixXd::Ones(1, 1)},
      {Eigen::MatrixXd::Constant(1, 1, 2.0), Eigen::MatrixXd::Ones(1, 1)},
      {Eigen::MatrixXd::Constant(1, 1, 1.0), Eigen::MatrixXd::Constant(1, 1, 3.0)}};
  const auto fn = gs::control::interpolate_linearisation(times, samples);
  REQUIRE(fn);
  CHECK(fn(0.5).A(0, 0) == Approx(1.0));
  CHECK(fn(1.5).A(0, 0) == Approx(1.5));
  CHECK(fn(1.5).B(0, 0) == Approx(2.0));
  CHECK(fn(-1.0).A(0, 0) == 0.0);
  CHECK(fn(9.0).B(0, 0) == 3.0);
  CHECK_FALSE(gs::control::interpolate_linearisation({0.0, 0.0}, {samples[0], samples[1]}));
  CHECK_FALSE(gs::control::interpolate_linearisation({0.0}, samples));

  const auto ok = solve_tv_lqr(fn, Eigen::MatrixXd::Ones(1, 1), Eigen::MatrixXd::Ones(1, 1),
                               Eigen::MatrixXd::Ones(1, 1), 0.0, 2.0);
  CHECK_FALSE(ok.empty());
  CHECK(solve_tv_lqr(fn, Eigen::MatrixXd::Ones(1, 1), Eigen::MatrixXd::Ones(1, 1),
                     Eigen::MatrixXd::Ones(1, 1), 2.0, 0.0)
            .empty());
  CHECK(solve_tv_lqr(fn, Eigen::MatrixXd::Ones(1, 1), -Eigen::MatrixXd::Ones(1, 1),
                     Eigen::MatrixXd::Ones(1, 1), 0.0, 2.0)
            .empty());
  CHECK(solve_tv_lqr(fn, Eigen::MatrixXd::Ones(2, 2), Eigen::MatrixXd::Ones(1, 1),
                     Eigen::MatrixXd::Ones(2, 2), 0.0, 2.0)
            .empty());
}
