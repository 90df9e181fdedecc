// The other process of dds_loopback_test and of bench_dds's cross-process benchmark: a
// motion-capture bridge in miniature. It joins the domain with the loopback configuration,
// publishes a NamedPoseArray on rt/poses every PERIOD_US (10 ms by default) with one body named
// after its tag, and exits 0 when an operator command with the given sequence number arrives (1
// when none did within 20 s). Its stamps are n * 5 ms for frame n, or with STAMP the steady clock
// (CLOCK_MONOTONIC, which every process on the host shares) when the frame is written.
// Usage: dds_loopback_peer DOMAIN TAG SEQUENCE [PERIOD_US [STAMP]]
#include <chrono>
#include <cstdlib>
#include <string>

#include "groundstation/dds/dds.hpp"
#include "groundstation/dds/mocap_conversion.hpp"

int main(int argc, char** argv) {
  using namespace std::chrono_literals;
  if (argc < 4 || argc > 6) return 2;
  const auto domain_id = static_cast<dds_domainid_t>(std::atoi(argv[1]));
  const std::string tag = argv[2];
  const auto sequence = static_cast<std::uint32_t>(std::strtoul(argv[3], nullptr, 10));
  const std::chrono::microseconds period(argc > 4 ? std::atol(argv[4]) : 10'000);
  const bool stamp = argc > 5 && std::string(argv[5]) == "STAMP";

  gs::dds::Domain domain(domain_id, gs::dds::loopback_config());
  gs::dds::Participant participant(domain);
  gs::dds::Writer<gs::dds::NamedPoseArray> mocap(participant);
  gs::dds::Reader<gs::dds::OperatorCommand> commands(participant);

  gs::estimation::MocapPose pose;
  pose.p_m = Eigen::Vector3d(1.0, 2.0, 3.0);
  gs::dds::MocapMessage message;
  const auto end = std::chrono::steady_clock::now() + 20s;
  for (std::uint64_t n = 1; std::chrono::steady_clock::now() < end; ++n) {
    const std::int64_t stamp_ns = stamp ? std::chrono::duration_cast<std::chrono::nanoseconds>(
                                              std::chrono::steady_clock::now().time_since_epoch())
                                              .count()
                                        : static_cast<std::int64_t>(n) * 5'000'000;
    message.clear(stamp_ns);
    message.add(tag, pose);
    mocap.write(message.message());
    if (const auto* c = commands.wait_take(period); c != nullptr && c->sequence_number == sequence) return 0;
  }
  return 1;
}
