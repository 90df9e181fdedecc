// The ground station's DDS topics through real Cyclone DDS participants (groundstation/dds):
// every topic's sample arrives whole, and each topic's QoS (docs/dds.md) behaves as promised.
// Each test case has its own domain id, configured to stay inside this process, so that nothing
// on the host's network (or a concurrent run of this test) takes part. Every wait is bounded.
#include "groundstation/dds/dds.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <cstring>
#include <string>
#include <vector>

#include "groundstation/dds/mocap_conversion.hpp"

using namespace std::chrono_literals;
using gs::dds::Domain;
using gs::dds::Participant;
using gs::dds::Reader;
using gs::dds::Writer;

namespace {

constexpr auto kWait = 5s;

// A domain and two participants in it: the publisher's and the subscriber's.
struct Arena {
  explicit Arena(dds_domainid_t id)
      : domain(id, gs::dds::in_process_config()), publisher(domain), subscriber(domain) {}
  Domain domain;
  Participant publisher;
  Participant subscriber;
};

// A writer and a reader of T's topic in a domain of their own, matched.
template <class T>
struct Link {
  explicit Link(dds_domainid_t id) : arena(id), writer(arena.publisher), reader(arena.subscriber) {
    REQUIRE(writer.wait_for_readers(1, kWait));
  }
  Arena arena;
  Writer<T> writer;
  Reader<T> reader;
};

pa_arena_Estimate estimate(double base) {
  pa_arena_Estimate e{};
  e.position_m = {base, base + 1, base + 2};
  e.velocity_mps = {base + 3, base + 4, base + 5};
  e.attitude = {1.0, 0.0, 0.0, 0.0};
  e.rate_radps = {base + 6, base + 7, base + 8};
  return e;
}

void check_equal(const pa_arena_Vec3& a, const pa_arena_Vec3& b) {
  CHECK(a.x == b.x);
  CHECK(a.y == b.y);
  CHECK(a.z == b.z);
}

void check_equal(const pa_arena_Estimate& a, const pa_arena_Estimate& b) {
  check_equal(a.position_m, b.position_m);
  check_equal(a.velocity_mps, b.velocity_mps);
  CHECK(a.attitude.w == b.attitude.w);
  CHECK(a.attitude.x == b.attitude.x);
  check_equal(a.rate_radps, b.rate_radps);
}

pa_arena_Event event(std::int64_t time_ns, pa_arena_EventKind kind, std::uint8_t vehicle,
                     const char* detail) {
  pa_arena_Event e{};
  e.time_ns = time_ns;
  e.kind = kind;
  e.vehicle = vehicle;
  std::strncpy(e.detail, detail, sizeof e.detail - 1);
  return e;
}

}  // namespace

TEST_CASE("A NamedPoseArray of three bodies arrives whole on rt/poses", "[dds]") {
  Link<gs::dds::NamedPoseArray> link(101);
  auto& writer = link.writer;
  auto& reader = link.reader;

  gs::estimation::MocapFrame frame;
  gs::estimation::MocapPose pose;
  pose.p_m = Eigen::Vector3d(0.5, -0.25, 2.0);
  pose.q = Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 1, 0).normalized()));
  frame.vehicle[0] = pose;
  frame.vehicle[1] = pose;
  frame.pole = pose;
  gs::dds::MocapMessage message;
  gs::dds::mocap_frame_to_dds(frame, 3'250'000'000, gs::dds::MocapBodyNames{}, message);
  writer.write(message.message());

  const gs::dds::NamedPoseArray* got = reader.wait_take(kWait);
  REQUIRE(got != nullptr);
  CHECK(got->header.stamp.sec == 3);
  CHECK(got->header.stamp.nanosec == 250'000'000u);
  CHECK(std::string(got->header.frame_id) == "world");
  REQUIRE(got->poses._length == 3);
  CHECK(std::string(got->poses._buffer[2].name) == "pole");

  const auto in = gs::dds::mocap_frame_from_dds(*got, gs::dds::MocapBodyNames{});
  REQUIRE(in.frame.pole);
  CHECK(in.frame.pole->p_m == pose.p_m);
  CHECK(in.frame.pole->q.isApprox(pose.q, 1e-14));
  CHECK(in.frame.vehicle[0]->p_m == pose.p_m);
}

TEST_CASE("The motion-capture topic has ROS 2's names", "[dds]") {
  CHECK(std::string(gs::dds::Topic<gs::dds::NamedPoseArray>::kName) == "rt/poses");
  CHECK(std::string(gs::dds::Topic<gs::dds::NamedPoseArray>::descriptor()->m_typename) ==
        "motion_capture_tracking_interfaces::msg::dds_::NamedPoseArray_");
}

TEST_CASE("Vehicle telemetry arrives whole", "[dds]") {
  Link<pa_arena_VehicleTelemetry> link(102);
  auto& writer = link.writer;
  auto& reader = link.reader;

  pa_arena_VehicleTelemetry sent{};
  sent.vehicle = pa::kVehicle2.node();
  sent.time_ns = 123'456'789;
  sent.link = pa_arena_link_up;
  sent.mode = 4;
  sent.vehicle_mode = 3;
  sent.estimate_valid = true;
  sent.estimate = estimate(10.0);
  writer.write(sent);

  const auto* got = reader.wait_take(kWait);
  REQUIRE(got != nullptr);
  CHECK(got->vehicle == pa::kVehicle2.node());
  CHECK(got->time_ns == sent.time_ns);
  CHECK(got->link == pa_arena_link_up);
  CHECK(got->mode == 4);
  CHECK(got->vehicle_mode == 3);
  CHECK(got->estimate_valid);
  check_equal(got->estimate, sent.estimate);
}

TEST_CASE("Pole telemetry arrives whole", "[dds]") {
  Link<pa_arena_PoleTelemetry> link(103);
  auto& writer = link.writer;
  auto& reader = link.reader;

  pa_arena_PoleTelemetry sent{};
  sent.time_ns = 5'000'000'000;
  sent.estimate_valid = true;
  sent.mode = pa_arena_pole_free;
  sent.estimate.position_m = {0.1, 0.2, 2.5};
  sent.estimate.velocity_mps = {1.0, 0.0, 3.0};
  sent.estimate.direction = {0.0, 0.6, 0.8};
  sent.estimate.rate_radps = {0.5, -2.0, 1.5};
  sent.catch_predicted = true;
  sent.catch_time_ns = 5'600'000'000;
  sent.catch_point_m = {1.0, 0.1, 1.3};
  sent.catch_vehicle = pa::kVehicle2.node();
  writer.write(sent);

  const auto* got = reader.wait_take(kWait);
  REQUIRE(got != nullptr);
  CHECK(got->time_ns == sent.time_ns);
  CHECK(got->mode == pa_arena_pole_free);
  check_equal(got->estimate.position_m, sent.estimate.position_m);
  check_equal(got->estimate.velocity_mps, sent.estimate.velocity_mps);
  check_equal(got->estimate.direction, sent.estimate.direction);
  check_equal(got->estimate.rate_radps, sent.estimate.rate_radps);
  CHECK(got->catch_predicted);
  CHECK(got->catch_time_ns == sent.catch_time_ns);
  check_equal(got->catch_point_m, sent.catch_point_m);
  CHECK(got->catch_vehicle == pa::kVehicle2.node());
}

TEST_CASE("An event arrives whole", "[dds]") {
  Link<pa_arena_Event> link(104);
  auto& writer = link.writer;
  auto& reader = link.reader;

  writer.write(event(42, pa_arena_event_catch_success, pa::kVehicle2.node(), "caught at 1.31 m"));
  const auto* got = reader.wait_take(kWait);
  REQUIRE(got != nullptr);
  CHECK(got->time_ns == 42);
  CHECK(got->kind == pa_arena_event_catch_success);
  CHECK(got->vehicle == pa::kVehicle2.node());
  CHECK(std::string(got->detail) == "caught at 1.31 m");
}

TEST_CASE("An operator command arrives whole", "[dds]") {
  Link<pa_arena_OperatorCommand> link(105);
  auto& writer = link.writer;
  auto& reader = link.reader;

  pa_arena_OperatorCommand sent{};
  sent.kind = pa_arena_command_kill;
  sent.target = 0;
  sent.sequence_number = 7;
  writer.write(sent);
  const auto* got = reader.wait_take(kWait);
  REQUIRE(got != nullptr);
  CHECK(got->kind == pa_arena_command_kill);
  CHECK(got->target == 0);
  CHECK(got->sequence_number == 7);
}

TEST_CASE("A mocap reader keeps only the latest frame", "[dds]") {
  Link<gs::dds::NamedPoseArray> link(106);
  auto& writer = link.writer;
  auto& reader = link.reader;

  // The frames told apart by their stamps, 1..5 ns.
  gs::dds::MocapMessage message;
  for (std::int64_t n = 1; n <= 5; ++n) {
    gs::dds::mocap_frame_to_dds(gs::estimation::MocapFrame{}, n, gs::dds::MocapBodyNames{}, message);
    writer.write(message.message());
  }
  // Keep last 1: frames 1..4 were replaced in the reader's cache. Frame 5 is the newest
  // written, so once it is there nothing else can follow it.
  std::int64_t last = 0;
  int taken = 0;
  while (last != 5) {
    const auto* got = reader.wait_take(kWait);
    REQUIRE(got != nullptr);
    CHECK(gs::dds::stamp_nanoseconds(got->header.stamp) > last);
    last = gs::dds::stamp_nanoseconds(got->header.stamp);
    ++taken;
  }
  CHECK(reader.take() == nullptr);
  // Within a process Cyclone delivers in dds_write itself, so after the burst the cache held
  // frame 5 alone.
  CHECK(taken == 1);
}

TEST_CASE("A mocap reader takes into the same sequence buffer frame after frame", "[dds]") {
  // No heap churn for the poses per frame: Cyclone allocates the reader's sequence on the first
  // frame and reuses it for frames of no more bodies.
  Link<gs::dds::NamedPoseArray> link(113);
  gs::estimation::MocapFrame frame;
  frame.vehicle[0] = gs::estimation::MocapPose{};
  frame.vehicle[1] = gs::estimation::MocapPose{};
  frame.pole = gs::estimation::MocapPose{};
  gs::dds::MocapMessage message;
  gs::dds::mocap_frame_to_dds(frame, 1, gs::dds::MocapBodyNames{}, message);
  link.writer.write(message.message());
  const gs::dds::NamedPoseArray* first = link.reader.wait_take(kWait);
  REQUIRE(first != nullptr);
  const gs::dds::NamedPose* buffer = first->poses._buffer;
  for (std::int64_t n = 2; n <= 4; ++n) {
    gs::dds::mocap_frame_to_dds(frame, n, gs::dds::MocapBodyNames{}, message);
    link.writer.write(message.message());
    const gs::dds::NamedPoseArray* got = link.reader.wait_take(kWait);
    REQUIRE(got != nullptr);
    CHECK(gs::dds::stamp_nanoseconds(got->header.stamp) == n);
    CHECK(got->poses._buffer == buffer);
    CHECK(std::string(got->poses._buffer[1].name) == "vehicle2");
  }
}

TEST_CASE("Vehicle telemetry keeps the latest sample of each vehicle", "[dds]") {
  Link<pa_arena_VehicleTelemetry> link(107);
  auto& writer = link.writer;
  auto& reader = link.reader;

  pa_arena_VehicleTelemetry t{};
  t.vehicle = pa::kVehicle1.node();
  t.time_ns = 1;
  writer.write(t);
  t.time_ns = 2;
  writer.write(t);
  t.vehicle = pa::kVehicle2.node();
  t.time_ns = 3;
  writer.write(t);

  std::vector<std::pair<int, std::int64_t>> got;
  while (got.size() < 2) {
    const auto* s = reader.wait_take(kWait);
    REQUIRE(s != nullptr);
    got.emplace_back(s->vehicle, s->time_ns);
  }
  CHECK(reader.take() == nullptr);
  std::sort(got.begin(), got.end());
  CHECK(got[0] == std::pair<int, std::int64_t>{1, 2});  // vehicle 1's first sample replaced
  CHECK(got[1] == std::pair<int, std::int64_t>{2, 3});  // vehicle 2's not pushed out by vehicle 1's
}

TEST_CASE("A late event reader receives the events published before it joined", "[dds]") {
  Arena arena(108);
  Writer<pa_arena_Event> writer(arena.publisher);
  writer.write(event(1, pa_arena_event_launch, pa::kVehicle1.node(), "launch"));
  writer.write(event(2, pa_arena_event_impact, pa::kVehicle2.node(), "impact"));
  writer.write(event(3, pa_arena_event_catch_miss, pa::kVehicle2.node(), "missed"));

  Reader<pa_arena_Event> late(arena.subscriber);
  for (std::int64_t t = 1; t <= 3; ++t) {
    const auto* got = late.wait_take(kWait);
    REQUIRE(got != nullptr);
    CHECK(got->time_ns == t);  // reliable: all of them, in order
  }
  CHECK(late.take() == nullptr);
}

TEST_CASE("A late command reader does not receive commands sent before it joined", "[dds]") {
  Arena arena(109);
  Writer<pa_arena_OperatorCommand> writer(arena.publisher);
  pa_arena_OperatorCommand command{};
  command.kind = pa_arena_command_throw;
  command.target = pa::kVehicle1.node();
  command.sequence_number = 1;
  writer.write(command);  // before any ground station listened: must not be acted on

  Reader<pa_arena_OperatorCommand> late(arena.subscriber);
  REQUIRE(writer.wait_for_readers(1, kWait));
  command.kind = pa_arena_command_land;
  command.sequence_number = 2;
  writer.write(command);
  // Volatile: a historical sample would have been delivered before the new one.
  const auto* got = late.wait_take(kWait);
  REQUIRE(got != nullptr);
  CHECK(got->sequence_number == 2);
  CHECK(got->kind == pa_arena_command_land);
}

TEST_CASE("The loopback configuration starts a domain and carries a sample", "[dds]") {
  // The configuration a ground station uses on one host (docs/dds.md). Another process on this
  // host in the same domain could take part; the sample is told apart by its detail.
  Domain domain(110, gs::dds::loopback_config());
  Participant publisher(domain);
  Participant subscriber(domain);
  Writer<pa_arena_Event> writer(publisher);
  Reader<pa_arena_Event> reader(subscriber);
  REQUIRE(writer.wait_for_readers(1, kWait));
  const std::string tag = "loopback " + std::to_string(reinterpret_cast<std::uintptr_t>(&domain));
  writer.write(event(9, pa_arena_event_abort, 0, tag.c_str()));
  bool found = false;
  const auto end = std::chrono::steady_clock::now() + kWait;
  while (!found && std::chrono::steady_clock::now() < end) {
    const auto* got = reader.wait_take(100ms);
    found = got != nullptr && std::string(got->detail) == tag;
  }
  CHECK(found);
}

TEST_CASE("A second domain with the same id is refused", "[dds]") {
  Domain domain(111, gs::dds::in_process_config());
  CHECK_THROWS_AS(Domain(111, gs::dds::in_process_config()), gs::dds::DdsError);
}
