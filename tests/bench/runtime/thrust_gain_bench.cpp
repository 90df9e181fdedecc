// The per-vehicle estimation's cost per ground-station frame: the thrust-gain estimator
// (groundstation/estimation/thrust_gain.hpp) given one pose and one command, as the runtime
// does for each vehicle at every motion-capture frame; a window's fit every 20th frame.
#include <benchmark/benchmark.h>

#include <cmath>

#include "groundstation/estimation/thrust_gain.hpp"

namespace {

void BM_ThrustGainPerFrame(benchmark::State& state) {
  gs::estimation::ThrustGainEstimator estimator;
  double t = 0.0;
  for (auto _ : state) {
    estimator.command(t + 0.012, 9.81 + 0.1 * std::sin(t));
    estimator.pose(t, 1.0 + 0.01 * std::sin(t), 0.999, 0.0, true);
    t += 0.005;
  }
  benchmark::DoNotOptimize(estimator.gain());
  state.counters["gain"] = estimator.gain();
}
BENCHMARK(BM_ThrustGainPerFrame);

}  // namespace
