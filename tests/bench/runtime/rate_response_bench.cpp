// The motor-lag identification's costs: recording a frame's command and telemetry during the
// take-off's doublets (every frame of the identification flight), and the fit (once per take-off).
// The data: the doublets through a 45 ms motor and the firmware's PI loop, at the radio's 200 Hz.
#include <benchmark/benchmark.h>

#include <cmath>

#include "groundstation/runtime/identification_flight.hpp"

namespace {

using gs::estimation::RateLoopConfig;
using gs::estimation::RateResponseIdentifier;

struct Recorded {
  std::vector<gs::estimation::RateCommandSample> commands;
  std::vector<gs::estimation::RateTelemetrySample> telemetry;
};

Recorded doublets(const RateResponseIdentifier& id) {
  const RateLoopConfig loop;
  Recorded r;
  double rate[2] = {0, 0}, integral[2] = {0, 0}, motor[2] = {0, 0};
  for (int k = 0; k * 0.001 < id.excitation_duration_s() + 0.3; ++k) {
    const double t = k * 0.001;
    const Eigen::Vector2d cmd = id.excitation(t - 0.01);  // 10 ms up
    if (k % 10 == 0) r.commands.push_back({t, id.excitation(t)});
    for (int a = 0; a < 2; ++a) {
      const double e = cmd[a] - rate[a];
      integral[a] += loop.ki_per_s2[a] * e * 0.001;
      const double u = loop.kp_per_s[a] * e + integral[a];
      motor[a] += (u * 0.045 / 0.03 - motor[a]) * (1.0 - std::exp(-0.001 / 0.045));
      rate[a] += motor[a] * 0.001;
    }
    if (k % 5 == 0) r.telemetry.push_back({t + 0.01, Eigen::Vector2d(rate[0], rate[1]), false});
  }
  return r;
}

void BM_MotorLagFit(benchmark::State& state) {
  const RateResponseIdentifier id{RateLoopConfig{}};
  const Recorded r = doublets(id);
  double lag = 0.0;
  for (auto _ : state) {
    const auto result = id.fit(r.commands, r.telemetry, 0.03);
    lag = result.identified ? result.identified->time_constant_s : 0.0;
    benchmark::DoNotOptimize(lag);
  }
  state.counters["lag_ms"] = 1e3 * lag;
}
BENCHMARK(BM_MotorLagFit)->Unit(benchmark::kMillisecond);

void BM_IdentificationRecordPerFrame(benchmark::State& state) {
  gs::runtime::IdentificationFlight flight;
  int frame = 0;
  for (auto _ : state) {
    if (frame % 300 == 0) flight.start(0.0, 0.03);  // a flight records ~260 frames
    const double t = 0.005 * (frame % 300);
    benchmark::DoNotOptimize(flight.excitation(t));
    flight.command_sent(t, Eigen::Vector2d(0.1, -0.1));
    flight.telemetry(t, Eigen::Vector2d(0.1, -0.1), false);
    ++frame;
  }
}
BENCHMARK(BM_IdentificationRecordPerFrame);

}  // namespace
