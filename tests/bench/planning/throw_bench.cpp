// The throw planner's cost: solving problem (34) with IPOPT (Hermite-Simpson, N = 100, exact
// sparse derivatives, straight-line initial guess; print_level 0) and designing its TV-LQR.
// Target for the solve: at most 100 ms. And the throw planned for a target (target_throw.hpp):
// 20 targets 2.5-4.5 m away all round, each at most 100 ms.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "groundstation/planning/target_throw.hpp"
#include "groundstation/planning/throw_planner.hpp"
#include "groundstation/planning/throw_tracking.hpp"

namespace {

void BM_ThrowSolve100Intervals(benchmark::State& state) {
  const gs::planning::ThrowProblem problem;
  gs::planning::ThrowSolverOptions options;
  options.intervals = 100;
  options.print_level = 0;
  gs::planning::ThrowPlan plan;
  for (auto _ : state) {
    plan = gs::planning::plan_throw(problem, options);
    // An int: this benchmark version's DoNotOptimize clobbers a double it is given (GCC 12).
    benchmark::DoNotOptimize(plan.iterations);
  }
  if (!plan.success) state.SkipWithError(plan.status.c_str());
  state.counters["ipopt_iterations"] = plan.iterations;
  state.counters["cost"] = plan.cost;
}
BENCHMARK(BM_ThrowSolve100Intervals)->Unit(benchmark::kMillisecond);

void BM_ThrowTvLqrDesign(benchmark::State& state) {
  const gs::planning::ThrowPlan plan = gs::planning::plan_throw(gs::planning::ThrowProblem{});
  if (!plan.success) {
    state.SkipWithError(plan.status.c_str());
    return;
  }
  for (auto _ : state) {
    const gs::planning::ThrowTracker tracker(plan.trajectory);
    benchmark::DoNotOptimize(tracker.valid());
  }
}
BENCHMARK(BM_ThrowTvLqrDesign)->Unit(benchmark::kMillisecond);

// One iteration plans all 20 targets of target_throw_test (yaw in 18-degree steps, distances
// cycling 2.5-4.5 m, heights about the Fig. 5 catch's) from one hover point; the counters are
// the per-plan wall times over every iteration, in ms (the Fig. 5 seed is planned once, outside).
void BM_TargetThrow20Targets(benchmark::State& state) {
  const gs::planning::TargetThrowPlanner planner;
  if (!planner.valid()) {
    state.SkipWithError("the Fig. 5 seed throw did not plan");
    return;
  }
  const Eigen::Vector3d hover(0.4, -0.7, 2.0);
  const double pi = std::acos(-1.0);
  double max_ms = 0.0, sum_ms = 0.0, worst_error_m = 0.0, worst_instant_error_m = 0.0;
  int plans = 0, failures = 0;
  for (auto _ : state) {
    for (int i = 0; i < 20; ++i) {
      const double yaw = i * pi / 10.0, distance = 2.5 + 0.5 * (i % 5);
      const Eigen::Vector3d target =
          hover + Eigen::Vector3d(distance * std::cos(yaw), distance * std::sin(yaw),
                                  planner.seed_catch_point().y() + 0.2 * std::sin(0.9 * i));
      const auto start = std::chrono::steady_clock::now();
      const gs::planning::TargetThrowPlan plan = planner.plan(hover, target);
      const double ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
      benchmark::DoNotOptimize(plan.solves);
      max_ms = std::max(max_ms, ms);
      sum_ms += ms;
      ++plans;
      if (!plan.success) ++failures;
      worst_error_m = std::max(worst_error_m, plan.prediction_error_m);
      worst_instant_error_m = std::max(worst_instant_error_m, plan.catching_instant_error_m);
    }
  }
  if (failures > 0) state.SkipWithError("a target throw did not plan");
  state.counters["plan_max_ms"] = max_ms;
  state.counters["plan_mean_ms"] = sum_ms / std::max(plans, 1);
  // The catch point predicted from the launch state at the target's height, and the optimal
  // catching instant's lower end, against the target.
  state.counters["worst_catch_point_error_m"] = worst_error_m;
  state.counters["worst_catching_instant_error_m"] = worst_instant_error_m;
}
BENCHMARK(BM_TargetThrow20Targets)->Unit(benchmark::kMillisecond);

}  // namespace
