// bench_firmware: the host's time per firmware tick and per frame decode.
#include <benchmark/benchmark.h>

#include "fw/mixer.hpp"
#include "fw/vehicle.hpp"
#include "pa/protocol.hpp"

using namespace pa::proto;

namespace {

// A vehicle armed and flying a hover setpoint stream: the 1 kHz tick as it runs in flight,
// periodic telemetry included (one task per tick by phase).
void BM_VehicleTickInFlight(benchmark::State& state) {
  fw::VehicleConfig config{};
  fw::Vehicle vehicle(config);
  std::uint32_t now_us = 0;  // wraps after 71 minutes of ticks, as the firmware's clock may
  std::uint64_t tick = 0;
  std::uint8_t sp = 0, hb = 0;
  auto feed = [&](bool arm) {
    Frame f;
    if (tick % 20 == 0 && encode(GsHeartbeat{now_us / 1000, 1, GroundState::active, hb++}, 15, f))
      vehicle.on_frame(f, now_us);
    if (tick % 5 == 0) {
      sp = static_cast<std::uint8_t>((sp + 1) & 0x0F);
      if (encode(RateThrust{{0.1f, -0.1f, 0.0f}, arm ? 0.0f : 9.81f, sp}, 1, f)) vehicle.on_frame(f, now_us);
    }
  };
  fw::ImuSample s;
  s.accel_mps2 = {0.0f, 0.0f, 9.81f};
  s.gyro_radps = {0.01f, -0.02f, 0.0f};
  for (int i = 0; i < 100; ++i, now_us += 1000, ++tick) {  // arm on the ground
    feed(true);
    if (i == 50) {
      Frame f;
      if (encode(Command{CommandCode::arm, 0, 1, 0}, 1, f)) vehicle.on_frame(f, now_us);
    }
    s.t_us = now_us;
    vehicle.tick(s);
    Frame f;
    while (vehicle.pop_tx(f)) {
    }
  }
  Frame drain;
  for (auto _ : state) {
    feed(false);
    s.t_us = now_us;
    benchmark::DoNotOptimize(vehicle.tick(s));
    while (vehicle.pop_tx(drain)) benchmark::DoNotOptimize(drain);
    now_us += 1000;
    ++tick;
  }
  state.counters["mode"] = static_cast<double>(vehicle.mode());
  if (vehicle.mode() != Mode::flying) state.SkipWithError("the vehicle is not flying");
}
BENCHMARK(BM_VehicleTickInFlight);

void BM_ProtocolDecodeRateThrust(benchmark::State& state) {
  Frame f;
  encode(RateThrust{{1.0f, -2.0f, 0.5f}, 9.81f, 3}, 1, f);
  Message m;
  for (auto _ : state) {
    benchmark::DoNotOptimize(decode(f, m));
    benchmark::DoNotOptimize(m);
  }
}
BENCHMARK(BM_ProtocolDecodeRateThrust);

void BM_ProtocolRejectWrongLength(benchmark::State& state) {
  Frame f;
  f.id = make_id(Type::rate_thrust, 1);
  f.len = 5;
  Message m;
  for (auto _ : state) benchmark::DoNotOptimize(decode(f, m));
}
BENCHMARK(BM_ProtocolRejectWrongLength);

void BM_MixerSaturated(benchmark::State& state) {
  fw::Mixer mixer{fw::AirframeConfig{}};
  const fw::MixerInput in{11.0f, {0.3f, -0.2f, 0.05f}};
  for (auto _ : state) benchmark::DoNotOptimize(mixer.mix(in));
}
BENCHMARK(BM_MixerSaturated);

}  // namespace
