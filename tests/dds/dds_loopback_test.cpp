// Two processes on the loopback configuration (docs/dds.md, "Running on one machine"): this
// test and dds_loopback_peer, a miniature motion-capture bridge, find each other by unicast
// discovery on 127.0.0.1 without multicast, and samples cross in both directions: the peer's
// best-effort NamedPoseArray frames to here, a reliable operator command back. Another run on this host
// may share the domain; this run's samples are told apart by a tag made of its process id.
#include <catch2/catch.hpp>
#include <chrono>
#include <string>

#include "groundstation/dds/dds.hpp"
#include "groundstation/dds/mocap_conversion.hpp"
#include "peer_process.hpp"

using namespace std::chrono_literals;

namespace {

constexpr dds_domainid_t kDomain = 112;

}  // namespace

TEST_CASE("A mocap bridge in another process is heard on loopback and hears a command", "[dds]") {
  const std::string tag = "peer" + std::to_string(getpid());
  const std::uint32_t sequence = static_cast<std::uint32_t>(getpid());

  gs::dds::Domain domain(kDomain, gs::dds::loopback_config());
  gs::dds::Participant participant(domain);
  gs::dds::Reader<gs::dds::NamedPoseArray> mocap(participant);
  gs::dds::Writer<gs::dds::OperatorCommand> commands(participant);

  const pid_t child = dds_test::start_peer({std::to_string(kDomain), tag, std::to_string(sequence)});
  REQUIRE(child > 0);

  // Discovery takes a few of Cyclone's SPDP rounds; the peer writes every 10 ms.
  bool heard = false;
  const auto end = std::chrono::steady_clock::now() + 15s;
  while (!heard && std::chrono::steady_clock::now() < end) {
    const gs::dds::NamedPoseArray* frame = mocap.wait_take(100ms);
    if (frame == nullptr || frame->poses._length != 1) continue;
    const gs::dds::NamedPose& body = frame->poses._buffer[0];
    if (std::string(body.name) != tag) continue;
    heard = true;
    CHECK(gs::dds::stamp_nanoseconds(frame->header.stamp) % 5'000'000 == 0);
    CHECK(body.pose.position.x == 1.0);
    CHECK(body.pose.position.y == 2.0);
    CHECK(body.pose.position.z == 3.0);
    CHECK(body.pose.orientation.w == 1.0);
  }
  CHECK(heard);

  gs::dds::OperatorCommand command{};
  command.kind = gs::dds::command_kind::kKill;
  command.sequence_number = sequence;
  if (heard) {
    // The peer's reader is matched by now (its writer is); reliable delivery does the rest.
    commands.wait_for_readers(1, 5s);
    commands.write(command);
  }
  CHECK(dds_test::wait_exit(child, 25s) == 0);
}
