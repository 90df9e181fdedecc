// The throw planner's cost: solving problem (34) with IPOPT (Hermite-Simpson, N = 100, exact
// sparse derivatives, straight-line initial guess; print_level 0) and designing its TV-LQR.
// Target for the solve: at most 100 ms.
#include <benchmark/benchmark.h>

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

}  // namespace
