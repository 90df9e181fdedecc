// Motion-capture delivery latency through Cyclone DDS (groundstation/dds): a writer publishes a
// pa_mocap frame of three rigid bodies (both vehicles and the pole) stamped with the steady clock
// as its capture time; a reader thread, blocked on a waitset, takes it and records now minus
// that stamp. Both participants are in this process and one domain, so Cyclone delivers within
// the process (no sockets); the figure is the DDS stack's own cost plus a thread wake-up, the
// floor under what a bridge in another process adds with the loopback's UDP.
//
// One frame in flight at a time (the next is written once the reader has taken the previous),
// as at 200 Hz, where 5 ms separate frames. Printed: latency_median_us, latency_p99_us.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

#include "groundstation/dds/dds.hpp"
#include "groundstation/dds/mocap_conversion.hpp"

namespace {

using namespace std::chrono_literals;

std::int64_t steady_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(p * static_cast<double>(v.size() - 1))];
}

void BM_MocapDeliveryLatency(benchmark::State& state) {
  gs::dds::Domain domain(120, gs::dds::in_process_config());
  gs::dds::Participant publisher(domain);
  gs::dds::Participant subscriber(domain);
  gs::dds::Writer<pa_arena_MocapFrame> writer(publisher);
  gs::dds::Reader<pa_arena_MocapFrame> reader(subscriber);
  if (!writer.wait_for_readers(1, 5s)) {
    state.SkipWithError("the reader did not match");
    return;
  }

  std::vector<double> latency_us;
  latency_us.reserve(static_cast<std::size_t>(state.max_iterations));
  std::atomic<std::uint64_t> taken{0};
  std::atomic<bool> stop{false};
  std::thread reading([&] {
    while (!stop.load()) {
      const pa_arena_MocapFrame* frame = reader.wait_take(100ms);
      if (frame == nullptr) continue;
      latency_us.push_back(1e-3 * static_cast<double>(steady_ns() - frame->capture_time_ns));
      taken.store(frame->frame_number);
    }
  });

  gs::estimation::MocapPose pose;
  pose.p_m = Eigen::Vector3d(0.5, -0.25, 2.0);
  gs::dds::MocapMessage message;
  std::uint64_t number = 0;
  bool lost = false;
  for (auto _ : state) {
    ++number;
    message.clear(number, steady_ns());
    for (const pa::VehicleId vehicle : pa::kActVehicles)
      message.add(gs::dds::vehicle_body_name(vehicle), pose);
    message.add(gs::dds::kPoleBody, pose);
    writer.write(message.message());
    const auto give_up = std::chrono::steady_clock::now() + 1s;
    while (taken.load() != number) {
      if (std::chrono::steady_clock::now() > give_up) {
        lost = true;
        break;
      }
      std::this_thread::yield();
    }
    if (lost) break;
  }
  stop.store(true);
  reading.join();
  if (lost) {
    state.SkipWithError("a frame did not arrive within 1 s");
    return;
  }
  state.counters["latency_median_us"] = percentile(latency_us, 0.5);
  state.counters["latency_p99_us"] = percentile(latency_us, 0.99);
  state.counters["frames"] = static_cast<double>(latency_us.size());
}
BENCHMARK(BM_MocapDeliveryLatency)->Unit(benchmark::kMicrosecond)->Iterations(20000)->UseRealTime();

}  // namespace
