// The catch planner's real-time cost (Section V: the catch is re-planned at every new catch-point
// prediction, 50 Hz in the paper). One replan = construct the trajectory, check it against the
// input limits, and evaluate the reference (state and nominal inputs) at the control ticks that
// run until the next replan: 4 ticks of the 200 Hz loop for a 50 Hz replan.
#include <benchmark/benchmark.h>

#include "groundstation/planning/catch_trajectory.hpp"

namespace {

using gs::planning::CatchTrajectory;
using gs::planning::CatchTrajectoryParams;

CatchTrajectoryParams fig7() {
  CatchTrajectoryParams p;
  p.target_xy_m = {0.25, 0.0};
  p.catch_height_m = 1.343;
  return p;
}

void BM_CatchTrajectoryWithFeasibility(benchmark::State& state) {
  CatchTrajectoryParams p = fig7();
  const gs::planning::InputLimits limits;
  constexpr int kTicks = 4;
  constexpr double kTick_s = 0.005;
  double jitter = 0.0;
  for (auto _ : state) {
    // Vary the target a little so nothing is hoisted out of the loop.
    jitter = jitter > 0.01 ? 0.0 : jitter + 1e-4;
    p.target_xy_m.x() = 0.25 + jitter;
    const auto traj = CatchTrajectory::create(p);
    const auto verdict = traj->check_feasibility(limits);
    const double t_now = traj->xy_start_time_s() + 0.1;
    double sum = 0.0;
    for (int k = 0; k < kTicks; ++k) {
      const auto ref = traj->reference(t_now + k * kTick_s);
      sum += ref.thrust_mps2 + ref.body_rates_radps.y() + ref.position_m.x();
    }
    benchmark::DoNotOptimize(sum);
    benchmark::DoNotOptimize(verdict);
  }
}
BENCHMARK(BM_CatchTrajectoryWithFeasibility);

// The feasibility check alone on the feasible Fig. 7 case (the bounds certify it at once).
void BM_CatchFeasibilityCheckFeasible(benchmark::State& state) {
  const auto traj = CatchTrajectory::create(fig7());
  const gs::planning::InputLimits limits;
  for (auto _ : state) benchmark::DoNotOptimize(traj->check_feasibility(limits));
}
BENCHMARK(BM_CatchFeasibilityCheckFeasible);

// The infeasible path: a violation is found, then every limit's worst value is located by a 1 ms
// scan of the xy phase.
void BM_CatchFeasibilityCheckInfeasible(benchmark::State& state) {
  CatchTrajectoryParams p = fig7();
  p.target_xy_m = {0.12, 0.0};
  p.t_xy_s = 0.35;  // rates too high
  const auto traj = CatchTrajectory::create(p);
  const gs::planning::InputLimits limits;
  for (auto _ : state) benchmark::DoNotOptimize(traj->check_feasibility(limits));
}
BENCHMARK(BM_CatchFeasibilityCheckInfeasible);

// The whole manoeuvre sampled at the 200 Hz control period (what a TV-LQR design along it needs).
void BM_CatchTrajectorySampleWhole5ms(benchmark::State& state) {
  const auto traj = CatchTrajectory::create(fig7());
  for (auto _ : state) {
    double sum = 0.0;
    for (double t = 0.0; t <= traj->duration_s(); t += 0.005) sum += traj->reference(t).thrust_mps2;
    benchmark::DoNotOptimize(sum);
  }
}
BENCHMARK(BM_CatchTrajectorySampleWhole5ms);

}  // namespace
