// The closed loop's cost: one whole ground-station frame (GroundStation::on_mocap: estimator
// update, latency compensation, mission, controllers and catch re-planning, link, both vehicles;
// the budget: a median of at most 50 us) and the whole arena (plant, two firmware cores, radios,
// motion capture and the ground station) as a multiple of real time on one core, both measured
// while flying a throw that adapts only and a catch (hil/trials/series.hpp). The Fig. 5 throw is
// planned once before, as a campaign plans it once for all its attempts (GroundStationConfig::
// fig5_throw): a flight does not plan it.
//
// Printed, per core (processor time, whatever else the machine runs): realtime_multiple, (b)
// the arena with the ground station; arena_realtime_multiple, (a) the arena alone (plant, both
// firmware cores, radios, motion capture: Arena::step) in the same flight, its calls timed by the
// wall clock (series.cpp); less_frames_realtime_multiple, the processor time less the
// ground-station frames (on_mocap), which also counts the ground station's construction,
// on_frame() and tick() and the runner's own work. Wall-clock times overstate
// under load, so they are scaled by the run's processor over wall time.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <vector>

#include "hil/trials/series.hpp"

namespace {

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(p * static_cast<double>(v.size() - 1))];
}

void BM_ClosedLoopThrowAndCatch(benchmark::State& state) {
  std::vector<double> frames;
  double simulated_s = 0.0, cpu_s = 0.0, ground_station_s = 0.0, arena_s = 0.0;
  const hil::trials::SeriesConfig defaults;
  const auto fig5 =
      gs::planning::plan_fig5_throw(defaults.ground_station.limits, defaults.ground_station.throw_tracking);
  for (auto _ : state) {
    hil::trials::SeriesConfig config;
    config.seed = 1;
    config.ground_station.fig5_throw = fig5;
    config.time_ground_station = true;
    config.time_arena = true;
    const std::clock_t start = std::clock();
    const auto wall_start = std::chrono::steady_clock::now();
    hil::trials::SeriesRunner runner(config);
    const auto results = runner.run(hil::trials::catch_series(2));
    // Processor time: the multiple per core, whatever else the machine runs.
    const double run_cpu_s = static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;
    const double run_wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    cpu_s += run_cpu_s;
    simulated_s += runner.simulated_time_s();
    const auto& t = runner.ground_station_frame_times_s();
    frames.insert(frames.end(), t.begin(), t.end());
    double run_ground_station_s = 0.0;
    for (const double s : t) run_ground_station_s += s;
    ground_station_s += run_ground_station_s * std::min(1.0, run_cpu_s / run_wall_s);
    arena_s += runner.arena_time_s() * std::min(1.0, run_cpu_s / run_wall_s);
    benchmark::DoNotOptimize(results);
  }
  state.counters["gs_frame_median_us"] = 1e6 * percentile(frames, 0.5);
  state.counters["gs_frame_p99_us"] = 1e6 * percentile(frames, 0.99);
  state.counters["gs_frames"] = static_cast<double>(frames.size());
  state.counters["realtime_multiple"] = simulated_s / cpu_s;
  state.counters["arena_realtime_multiple"] = simulated_s / arena_s;
  state.counters["less_frames_realtime_multiple"] = simulated_s / (cpu_s - ground_station_s);
  state.counters["simulated_s"] = simulated_s;
}
BENCHMARK(BM_ClosedLoopThrowAndCatch)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace
