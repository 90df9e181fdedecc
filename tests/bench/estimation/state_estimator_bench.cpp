// The estimator's cost per motion-capture frame (the budget: one full update, two vehicles, the
// pole and the mode selection, in at most 20 us), on a throw recorded in the tests' truth world,
// per phase, and the parts it is made of.
#include <benchmark/benchmark.h>

#include "../../groundstation/estimation_test_feed.hpp"
#include "groundstation/estimation/state_estimator.hpp"
#include "groundstation/planning/catch_point_predictor.hpp"

namespace {

using estimation_test::Frame;
using estimation_test::Recording;
using gs::estimation::MocapFrame;
using gs::estimation::StateEstimator;
using estimation_test::to_input;
using estimation_test::to_mocap;

const Recording& throw_recording() {
  static const Recording rec = estimation_test::record_throw(estimation_test::WorldParams{}, 1);
  return rec;
}

void feed(StateEstimator& est, const Frame& f, const MocapFrame& m) {
  est.update(m);
  est.set_command(pa::kVehicle1, f.t_s, to_input(f.command[0]));
  est.set_command(pa::kVehicle2, f.t_s, to_input(f.command[1]));
}

// Frames [first, last) of the throw, one update (with its two commands) per iteration; the
// estimator is restored to its state at `first` (untimed) when the range is used up.
void run_frames(benchmark::State& state, double from_s, double to_s) {
  const Recording& rec = throw_recording();
  std::vector<MocapFrame> frames;
  for (const Frame& f : rec.frames) frames.push_back(to_mocap(f));
  std::size_t first = 0;
  while (first < rec.frames.size() && rec.frames[first].t_s < from_s) ++first;
  std::size_t last = first;
  while (last < rec.frames.size() && rec.frames[last].t_s < to_s) ++last;
  StateEstimator start;
  for (std::size_t i = 0; i < first; ++i) feed(start, rec.frames[i], frames[i]);
  StateEstimator est = start;
  std::size_t i = first;
  for (auto _ : state) {
    feed(est, rec.frames[i], frames[i]);
    benchmark::DoNotOptimize(est.time());
    if (++i == last) {
      state.PauseTiming();
      est = start;
      i = first;
      state.ResumeTiming();
    }
  }
  state.counters["frames"] = static_cast<double>(last - first);
}

// The whole throw: balancing, throw manoeuvre, launch, free flight, impact, after the catch.
void BM_EstimatorUpdateWholeThrow(benchmark::State& state) { run_frames(state, 0.0, 1e9); }
BENCHMARK(BM_EstimatorUpdateWholeThrow)->Unit(benchmark::kMicrosecond);

// The pole balanced on vehicle 1 (on-vehicle filter active, free-flight candidate).
void BM_EstimatorUpdateBalanced(benchmark::State& state) { run_frames(state, 0.2, 1.0); }
BENCHMARK(BM_EstimatorUpdateBalanced)->Unit(benchmark::kMicrosecond);

// Free flight (free-flight filter active, on-vehicle candidates where a plate is near).
void BM_EstimatorUpdateFreeFlight(benchmark::State& state) {
  const Recording& rec = throw_recording();
  run_frames(state, *rec.launch_t + 0.02, *rec.impact_t - 0.01);
}
BENCHMARK(BM_EstimatorUpdateFreeFlight)->Unit(benchmark::kMicrosecond);

// The last 50 ms before the impact and the impact itself: the catcher's candidate filter runs
// and the switch happens.
void BM_EstimatorUpdateAroundImpact(benchmark::State& state) {
  const Recording& rec = throw_recording();
  run_frames(state, *rec.impact_t - 0.05, *rec.impact_t + 0.02);
}
BENCHMARK(BM_EstimatorUpdateAroundImpact)->Unit(benchmark::kMicrosecond);

// Latency compensation: the estimate propagated 30 ms ahead (a copy and six 5 ms steps).
void BM_EstimatorPredict30ms(benchmark::State& state) {
  const Recording& rec = throw_recording();
  StateEstimator est(estimation_test::estimator_for());
  for (const Frame& f : rec.frames) {
    if (f.t_s > *rec.launch_t + 0.2) break;
    feed(est, f, to_mocap(f));
  }
  for (auto _ : state) benchmark::DoNotOptimize(est.predict_pole(est.time() + 0.03));
}
BENCHMARK(BM_EstimatorPredict30ms)->Unit(benchmark::kMicrosecond);

// The catch-point prediction the CLI adds per free-flight frame (planning, not the estimator).
void BM_CatchPointPredictionFromEstimate(benchmark::State& state) {
  const Recording& rec = throw_recording();
  StateEstimator est(estimation_test::estimator_for());
  for (const Frame& f : rec.frames) {
    if (f.t_s > *rec.launch_t + 0.1) break;
    feed(est, f, to_mocap(f));
  }
  const gs::model::PoleState s = est.pole().state;
  const gs::model::PoleParams p = est.pole_model();
  for (auto _ : state) {
    benchmark::DoNotOptimize(gs::planning::predict_catch_point(s, rec.catch_height, p));
  }
}
BENCHMARK(BM_CatchPointPredictionFromEstimate)->Unit(benchmark::kMicrosecond);

// The parts: one free-flight EKF step (predict 5 ms with its Jacobian, then update).
void BM_FreeFlightEkfPredictUpdate(benchmark::State& state) {
  const Recording& rec = throw_recording();
  StateEstimator est(estimation_test::estimator_for());
  for (const Frame& f : rec.frames) {
    if (f.t_s > *rec.launch_t + 0.1) break;
    feed(est, f, to_mocap(f));
  }
  const gs::estimation::PoleFreeFlightEkf start = est.free_flight_filter();
  gs::estimation::PoleFreeFlightEkf ekf = start;
  const gs::estimation::PoleMeasurement m{start.state().p_m, start.state().n};
  int n = 0;
  for (auto _ : state) {
    ekf.predict(0.005);
    benchmark::DoNotOptimize(ekf.update(m));
    if (++n == 50) {
      ekf = start;
      n = 0;
    }
  }
}
BENCHMARK(BM_FreeFlightEkfPredictUpdate)->Unit(benchmark::kMicrosecond);

// One vehicle observer step (predict 5 ms with a command, then update).
void BM_VehicleObserverPredictUpdate(benchmark::State& state) {
  const Recording& rec = throw_recording();
  gs::estimation::VehicleObserver obs(estimation_test::observer_for());
  obs.reset(to_pose(rec.frames[0].vehicle[0]));
  const gs::model::VehicleInput in{9.81, Eigen::Vector3d(0.1, -0.2, 0.0)};
  std::size_t i = 0;
  for (auto _ : state) {
    obs.predict(0.005, &in);
    benchmark::DoNotOptimize(obs.update(to_pose(rec.frames[i].vehicle[0])));
    i = (i + 1) % 100;
  }
}
BENCHMARK(BM_VehicleObserverPredictUpdate)->Unit(benchmark::kMicrosecond);

}  // namespace
