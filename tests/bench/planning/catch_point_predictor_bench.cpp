// The catch-point predictor runs at every motion-capture frame (200 Hz); target < 20 us per call.
// The worst case is the first call, right after the launch: it integrates the whole flight.
#include <benchmark/benchmark.h>

#include "groundstation/planning/catch_point_predictor.hpp"
#include "groundstation/planning/catching_instant.hpp"

namespace {

// One prediction from the Fig. 5 launch state to the nominal catching height (the whole free
// flight, ~1.2 s, with drag).
void BM_CatchPointPrediction(benchmark::State& state) {
  const gs::model::PoleParams params;
  const gs::model::PoleState launch =
      gs::planning::pole_state_at_launch(gs::planning::fig5_launch_state(), params);
  const double height = gs::planning::find_catching_instant(launch, params).catch_height_m;
  gs::model::PoleState pole = launch;
  for (auto _ : state) {
    benchmark::DoNotOptimize(pole);
    const gs::planning::CatchPointPrediction p = gs::planning::predict_catch_point(pole, height, params);
    benchmark::DoNotOptimize(p);
  }
  state.counters["flight_s"] = gs::planning::predict_catch_point(launch, height, params).t_s;
}
BENCHMARK(BM_CatchPointPrediction)->Unit(benchmark::kMicrosecond);

// One evaluation of f_p (20) with drag, the predictor's inner cost (4 per RK4 step).
void BM_PoleFreeFlightDerivative(benchmark::State& state) {
  const gs::model::PoleParams params;
  gs::model::PoleState pole = gs::planning::pole_state_at_launch(gs::planning::fig5_launch_state(), params);
  for (auto _ : state) {
    benchmark::DoNotOptimize(pole);
    benchmark::DoNotOptimize(gs::model::pole_free_flight_derivative(pole, params));
  }
}
BENCHMARK(BM_PoleFreeFlightDerivative);

}  // namespace
