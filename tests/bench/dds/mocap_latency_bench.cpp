// Motion-capture delivery latency through Cyclone DDS (groundstation/dds): a writer publishes a
// NamedPoseArray (rt/poses) of three bodies (both vehicles and the pole) stamped with the steady
// clock; a reader thread, blocked on a waitset, takes it and records now minus
// that stamp. Both participants are in this process and one domain, so Cyclone delivers within
// the process (no sockets); the figure is the DDS stack's own cost plus a thread wake-up, the
// floor under what a bridge in another process adds with the loopback's UDP.
//
// One frame in flight at a time (the next is written once the reader has taken the previous),
// as at 200 Hz, where 5 ms separate frames. Printed: latency_median_us, latency_p99_us.
//
// BM_MocapDeliveryLatencyAcrossProcesses: the same frame's trip from another process, the
// miniature bridge dds_loopback_peer (tests/dds/loopback_peer.cpp), over UDP on 127.0.0.1 with
// the loopback configuration: serialisation, the socket, Cyclone's receive thread, the reader's
// wake-up. The peer stamps each frame with CLOCK_MONOTONIC, which both processes share, and
// publishes one every millisecond; this benchmark takes one per iteration (its body is one rigid
// body, named with the run's tag, so that another run on the host is told apart).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include "../../dds/peer_process.hpp"
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

void report(benchmark::State& state, const std::vector<double>& latency_us) {
  state.counters["latency_median_us"] = percentile(latency_us, 0.5);
  state.counters["latency_p99_us"] = percentile(latency_us, 0.99);
  state.counters["frames"] = static_cast<double>(latency_us.size());
}

void BM_MocapDeliveryLatency(benchmark::State& state) {
  gs::dds::Domain domain(120, gs::dds::in_process_config());
  gs::dds::Participant publisher(domain);
  gs::dds::Participant subscriber(domain);
  gs::dds::Writer<gs::dds::NamedPoseArray> writer(publisher);
  gs::dds::Reader<gs::dds::NamedPoseArray> reader(subscriber);
  if (!writer.wait_for_readers(1, 5s)) {
    state.SkipWithError("the reader did not match");
    return;
  }

  std::vector<double> latency_us;
  latency_us.reserve(static_cast<std::size_t>(state.max_iterations));
  std::atomic<std::int64_t> taken{0};  // the stamp of the frame taken last
  std::atomic<bool> stop{false};
  std::thread reading([&] {
    while (!stop.load()) {
      const gs::dds::NamedPoseArray* frame = reader.wait_take(100ms);
      if (frame == nullptr) continue;
      const std::int64_t stamp_ns = gs::dds::stamp_nanoseconds(frame->header.stamp);
      latency_us.push_back(1e-3 * static_cast<double>(steady_ns() - stamp_ns));
      taken.store(stamp_ns);
    }
  });

  gs::estimation::MocapPose pose;
  pose.p_m = Eigen::Vector3d(0.5, -0.25, 2.0);
  gs::dds::MocapMessage message;
  const gs::dds::MocapBodyNames names;
  bool lost = false;
  for (auto _ : state) {
    const std::int64_t stamp_ns = steady_ns();
    message.clear(stamp_ns);
    for (const pa::VehicleId vehicle : pa::kActVehicles) message.add(names.vehicle(vehicle), pose);
    message.add(names.pole, pose);
    writer.write(message.message());
    const auto give_up = std::chrono::steady_clock::now() + 1s;
    while (taken.load() != stamp_ns) {
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
  report(state, latency_us);
}
BENCHMARK(BM_MocapDeliveryLatency)->Unit(benchmark::kMicrosecond)->Iterations(20000)->UseRealTime();

void BM_MocapDeliveryLatencyAcrossProcesses(benchmark::State& state) {
  gs::dds::Domain domain(121, gs::dds::loopback_config());
  gs::dds::Participant participant(domain);
  gs::dds::Reader<gs::dds::NamedPoseArray> reader(participant);
  gs::dds::Writer<gs::dds::OperatorCommand> commands(participant);

  const std::string tag = "bench" + std::to_string(getpid());
  const pid_t peer = dds_test::start_peer({"121", tag, std::to_string(getpid()), "1000", "STAMP"});
  if (peer <= 0) {
    state.SkipWithError("cannot start dds_loopback_peer");
    return;
  }
  // Takes the run's next frame; nullptr when none came within 5 s (the first: discovery).
  const auto next = [&]() -> const gs::dds::NamedPoseArray* {
    const auto end = std::chrono::steady_clock::now() + 5s;
    while (std::chrono::steady_clock::now() < end) {
      const gs::dds::NamedPoseArray* frame = reader.wait_take(100ms);
      if (frame != nullptr && frame->poses._length == 1 && tag == frame->poses._buffer[0].name) return frame;
    }
    return nullptr;
  };

  std::vector<double> latency_us;
  latency_us.reserve(static_cast<std::size_t>(state.max_iterations));
  bool lost = next() == nullptr;
  if (!lost) {
    for (auto _ : state) {
      const gs::dds::NamedPoseArray* frame = next();
      if (frame == nullptr) {
        lost = true;
        break;
      }
      latency_us.push_back(
          1e-3 * static_cast<double>(steady_ns() - gs::dds::stamp_nanoseconds(frame->header.stamp)));
    }
  }
  gs::dds::OperatorCommand stop{};
  stop.kind = gs::dds::command_kind::kKill;
  stop.sequence_number = static_cast<std::uint32_t>(getpid());
  commands.wait_for_readers(1, 2s);
  commands.write(stop);
  dds_test::wait_exit(peer, 10s);
  if (lost) {
    state.SkipWithError("the peer's frames did not arrive");
    return;
  }
  report(state, latency_us);
}
BENCHMARK(BM_MocapDeliveryLatencyAcrossProcesses)
    ->Unit(benchmark::kMicrosecond)
    ->Iterations(3000)
    ->UseRealTime();

}  // namespace
