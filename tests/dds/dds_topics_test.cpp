// The ground station's DDS topics through real Cyclone DDS participants (groundstation/dds):
// every topic's sample arrives whole, and each topic's QoS (docs/dds.md) behaves as promised.
// Each test case has its own domain id, configured to stay inside this process, so that nothing
// on the host's network (or a concurrent run of this test) takes part. Every wait is bounded.
#include "groundstation/dds/dds.hpp"

#include <catch2/catch.hpp>
#include <chrono>
#include <cstring>
#include <string>

#include "groundstation/dds/mocap_conversion.hpp"
#include "groundstation/dds/telemetry_conversion.hpp"

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
  explicit Link(dds_domainid_t id, const char* name = gs::dds::Topic<T>::kName)
      : arena(id), writer(arena.publisher, name), reader(arena.subscriber, name) {
    REQUIRE(writer.wait_for_readers(1, kWait));
  }
  Arena arena;
  Writer<T> writer;
  Reader<T> reader;
};

template <class A, class B>
void check_equal(const A& a, const B& b) {
  CHECK(a.x == b.x);
  CHECK(a.y == b.y);
  CHECK(a.z == b.z);
}

gs::dds::Event event(std::int64_t stamp_ns, std::uint8_t kind, std::uint8_t vehicle, const char* detail) {
  gs::dds::Event e{};
  e.stamp = gs::dds::ros_time(stamp_ns);
  e.kind = kind;
  e.vehicle = vehicle;
  std::strncpy(e.detail, detail, sizeof e.detail - 1);
  return e;
}

std::int64_t stamp_ns(const builtin_interfaces_msg_dds__Time_& stamp) {
  return gs::dds::stamp_nanoseconds(stamp);
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

TEST_CASE("The project's topics have ROS 2's names and pa_msgs' types", "[dds]") {
  CHECK(gs::dds::vehicle_telemetry_topic(pa::kVehicle2) == "rt/pa/vehicle2/telemetry");
  CHECK(gs::dds::vehicle_telemetry_topic(pa::VehicleId(3)).empty());
  CHECK(std::string(gs::dds::Topic<gs::dds::PoleTelemetry>::kName) == "rt/pa/pole/telemetry");
  CHECK(std::string(gs::dds::Topic<gs::dds::Event>::kName) == "rt/pa/events");
  CHECK(std::string(gs::dds::Topic<gs::dds::OperatorCommand>::kName) == "rt/pa/operator_commands");
  CHECK(std::string(gs::dds::Topic<gs::dds::VehicleTelemetry>::descriptor()->m_typename) ==
        "pa_msgs::msg::dds_::VehicleTelemetry_");
  CHECK(std::string(gs::dds::Topic<gs::dds::PoleTelemetry>::descriptor()->m_typename) ==
        "pa_msgs::msg::dds_::PoleTelemetry_");
  CHECK(std::string(gs::dds::Topic<gs::dds::Event>::descriptor()->m_typename) ==
        "pa_msgs::msg::dds_::Event_");
  CHECK(std::string(gs::dds::Topic<gs::dds::OperatorCommand>::descriptor()->m_typename) ==
        "pa_msgs::msg::dds_::OperatorCommand_");
}

TEST_CASE("Vehicle telemetry arrives whole", "[dds]") {
  const std::string topic = gs::dds::vehicle_telemetry_topic(pa::kVehicle2);
  Link<gs::dds::VehicleTelemetry> link(102, topic.c_str());
  auto& writer = link.writer;
  auto& reader = link.reader;

  gs::dds::VehicleTelemetry sent{};
  sent.stamp = gs::dds::ros_time(1'700'000'000'123'456'789);
  sent.vehicle = pa::kVehicle2.node();
  sent.link = gs::dds::link_state::kUp;
  sent.task = 4;
  sent.vehicle_mode = 3;
  sent.estimate_valid = true;
  sent.position = {10.0, 11.0, 12.0};
  sent.velocity = {13.0, 14.0, 15.0};
  sent.orientation = {0.0, 0.0, 0.6, 0.8};
  sent.body_rate = {16.0, 17.0, 18.0};
  writer.write(sent);

  const auto* got = reader.wait_take(kWait);
  REQUIRE(got != nullptr);
  CHECK(stamp_ns(got->stamp) == 1'700'000'000'123'456'789);
  CHECK(got->vehicle == pa::kVehicle2.node());
  CHECK(got->link == gs::dds::link_state::kUp);
  CHECK(got->task == 4);
  CHECK(got->vehicle_mode == 3);
  CHECK(got->estimate_valid);
  check_equal(got->position, sent.position);
  check_equal(got->velocity, sent.velocity);
  check_equal(got->orientation, sent.orientation);
  CHECK(got->orientation.w == 0.8);
  check_equal(got->body_rate, sent.body_rate);
}

TEST_CASE("Pole telemetry arrives whole", "[dds]") {
  Link<gs::dds::PoleTelemetry> link(103);
  auto& writer = link.writer;
  auto& reader = link.reader;

  gs::dds::PoleTelemetry sent{};
  sent.stamp = gs::dds::ros_time(5'000'000'000);
  sent.estimate_valid = true;
  sent.mode = gs::dds::pole_mode::kFree;
  sent.position = {0.1, 0.2, 2.5};
  sent.velocity = {1.0, 0.0, 3.0};
  sent.direction = {0.0, 0.6, 0.8};
  sent.angular_velocity = {0.5, -2.0, 1.5};
  sent.catch_predicted = true;
  sent.catch_stamp = gs::dds::ros_time(5'600'000'000);
  sent.catch_point = {1.0, 0.1, 1.3};
  sent.catch_vehicle = pa::kVehicle2.node();
  writer.write(sent);

  const auto* got = reader.wait_take(kWait);
  REQUIRE(got != nullptr);
  CHECK(stamp_ns(got->stamp) == 5'000'000'000);
  CHECK(got->mode == gs::dds::pole_mode::kFree);
  check_equal(got->position, sent.position);
  check_equal(got->velocity, sent.velocity);
  check_equal(got->direction, sent.direction);
  check_equal(got->angular_velocity, sent.angular_velocity);
  CHECK(got->catch_predicted);
  CHECK(stamp_ns(got->catch_stamp) == 5'600'000'000);
  check_equal(got->catch_point, sent.catch_point);
  CHECK(got->catch_vehicle == pa::kVehicle2.node());
}

TEST_CASE("An event arrives whole", "[dds]") {
  Link<gs::dds::Event> link(104);
  auto& writer = link.writer;
  auto& reader = link.reader;

  writer.write(event(42, gs::dds::event_kind::kCatchSuccess, pa::kVehicle2.node(), "caught at 1.31 m"));
  const auto* got = reader.wait_take(kWait);
  REQUIRE(got != nullptr);
  CHECK(stamp_ns(got->stamp) == 42);
  CHECK(got->kind == gs::dds::event_kind::kCatchSuccess);
  CHECK(got->vehicle == pa::kVehicle2.node());
  CHECK(std::string(got->detail) == "caught at 1.31 m");
}

TEST_CASE("An operator command arrives whole", "[dds]") {
  Link<gs::dds::OperatorCommand> link(105);
  auto& writer = link.writer;
  auto& reader = link.reader;

  gs::dds::OperatorCommand sent{};
  sent.kind = gs::dds::command_kind::kKill;
  sent.target = 0;
  sent.sequence_number = 7;
  writer.write(sent);
  const auto* got = reader.wait_take(kWait);
  REQUIRE(got != nullptr);
  CHECK(got->kind == gs::dds::command_kind::kKill);
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

TEST_CASE("Vehicle telemetry keeps the latest sample of each vehicle, on its own topic", "[dds]") {
  // ROS 2 messages have no keys: a topic per vehicle, so that vehicle 1's updates never push
  // vehicle 2's out of a reader's cache.
  Arena arena(107);
  const std::string topic1 = gs::dds::vehicle_telemetry_topic(pa::kVehicle1);
  const std::string topic2 = gs::dds::vehicle_telemetry_topic(pa::kVehicle2);
  Writer<gs::dds::VehicleTelemetry> writer1(arena.publisher, topic1.c_str());
  Writer<gs::dds::VehicleTelemetry> writer2(arena.publisher, topic2.c_str());
  Reader<gs::dds::VehicleTelemetry> reader1(arena.subscriber, topic1.c_str());
  Reader<gs::dds::VehicleTelemetry> reader2(arena.subscriber, topic2.c_str());
  REQUIRE(writer1.wait_for_readers(1, kWait));
  REQUIRE(writer2.wait_for_readers(1, kWait));

  gs::dds::VehicleTelemetry t{};
  t.vehicle = pa::kVehicle1.node();
  t.stamp = gs::dds::ros_time(1);
  writer1.write(t);
  t.stamp = gs::dds::ros_time(2);
  writer1.write(t);
  t.vehicle = pa::kVehicle2.node();
  t.stamp = gs::dds::ros_time(3);
  writer2.write(t);

  // Keep last 1: vehicle 1's first sample was replaced; vehicle 2's is there.
  std::int64_t last1 = 0;
  while (last1 != 2) {
    const auto* s = reader1.wait_take(kWait);
    REQUIRE(s != nullptr);
    CHECK(s->vehicle == 1);
    last1 = stamp_ns(s->stamp);
  }
  const auto* s = reader2.wait_take(kWait);
  REQUIRE(s != nullptr);
  CHECK(s->vehicle == 2);
  CHECK(stamp_ns(s->stamp) == 3);
  CHECK(reader1.take() == nullptr);
  CHECK(reader2.take() == nullptr);
}

TEST_CASE("A late event reader receives the events published before it joined", "[dds]") {
  Arena arena(108);
  Writer<gs::dds::Event> writer(arena.publisher);
  writer.write(event(1, gs::dds::event_kind::kLaunch, pa::kVehicle1.node(), "launch"));
  writer.write(event(2, gs::dds::event_kind::kImpact, pa::kVehicle2.node(), "impact"));
  writer.write(event(3, gs::dds::event_kind::kCatchMiss, pa::kVehicle2.node(), "missed"));

  Reader<gs::dds::Event> late(arena.subscriber);
  for (std::int64_t t = 1; t <= 3; ++t) {
    const auto* got = late.wait_take(kWait);
    REQUIRE(got != nullptr);
    CHECK(stamp_ns(got->stamp) == t);  // reliable: all of them, in order
  }
  CHECK(late.take() == nullptr);
}

TEST_CASE("A late command reader does not receive commands sent before it joined", "[dds]") {
  Arena arena(109);
  Writer<gs::dds::OperatorCommand> writer(arena.publisher);
  gs::dds::OperatorCommand command{};
  command.kind = gs::dds::command_kind::kThrow;
  command.target = pa::kVehicle1.node();
  command.sequence_number = 1;
  writer.write(command);  // before any ground station listened: must not be acted on

  Reader<gs::dds::OperatorCommand> late(arena.subscriber);
  REQUIRE(writer.wait_for_readers(1, kWait));
  command.kind = gs::dds::command_kind::kLand;
  command.sequence_number = 2;
  writer.write(command);
  // Volatile: a historical sample would have been delivered before the new one.
  const auto* got = late.wait_take(kWait);
  REQUIRE(got != nullptr);
  CHECK(got->sequence_number == 2);
  CHECK(got->kind == gs::dds::command_kind::kLand);
}

TEST_CASE("The loopback configuration starts a domain and carries a sample", "[dds]") {
  // The configuration a ground station uses on one host (docs/dds.md). Another process on this
  // host in the same domain could take part; the sample is told apart by its detail.
  Domain domain(110, gs::dds::loopback_config());
  Participant publisher(domain);
  Participant subscriber(domain);
  Writer<gs::dds::Event> writer(publisher);
  Reader<gs::dds::Event> reader(subscriber);
  REQUIRE(writer.wait_for_readers(1, kWait));
  const std::string tag = "loopback " + std::to_string(reinterpret_cast<std::uintptr_t>(&domain));
  writer.write(event(9, gs::dds::event_kind::kAbort, 0, tag.c_str()));
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
