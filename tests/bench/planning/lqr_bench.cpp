// The LQR designs' cost: the balancing CARE (13 states, 4 inputs) and the hover CARE (9 states).
#include <benchmark/benchmark.h>

#include "groundstation/control/balancing_lqr.hpp"
#include "groundstation/control/hover_lqr.hpp"
#include "groundstation/control/riccati.hpp"
#include "groundstation/control/tvlqr.hpp"

namespace {

// The CARE solve of the balancing design (sign function + Newton-Kleinman refinement), from the
// linearisation and weights to K and P.
void BM_CareSolveBalancing(benchmark::State& state) {
  const auto sys = gs::control::balancing_linearisation();
  const auto w = gs::control::balancing_lqr_weights();
  const Eigen::MatrixXd Q = w.state.asDiagonal();
  const Eigen::MatrixXd R = w.input.asDiagonal();
  for (auto _ : state) benchmark::DoNotOptimize(gs::control::solve_care(sys.A, sys.B, Q, R));
}
BENCHMARK(BM_CareSolveBalancing)->Unit(benchmark::kMicrosecond);

void BM_CareSolveHover(benchmark::State& state) {
  const auto sys = gs::control::hover_linearisation();
  const auto w = gs::control::hover_lqr_weights();
  const Eigen::MatrixXd Q = w.state.asDiagonal();
  const Eigen::MatrixXd R = w.input.asDiagonal();
  for (auto _ : state) benchmark::DoNotOptimize(gs::control::solve_care(sys.A, sys.B, Q, R));
}
BENCHMARK(BM_CareSolveHover)->Unit(benchmark::kMicrosecond);

// The TV-LQR of the hover model over a 1.8 s catch-length horizon (RK4 at 1 ms, gains at 5 ms).
void BM_TvLqrHover1800ms(benchmark::State& state) {
  const auto sys = gs::control::hover_linearisation();
  const auto w = gs::control::hover_lqr_weights();
  const Eigen::MatrixXd Q = w.state.asDiagonal();
  const Eigen::MatrixXd R = w.input.asDiagonal();
  for (auto _ : state) {
    benchmark::DoNotOptimize(gs::control::solve_tv_lqr([&](double) { return sys; }, Q, R, Q, 0.0, 1.8));
  }
}
BENCHMARK(BM_TvLqrHover1800ms)->Unit(benchmark::kMillisecond);

}  // namespace
