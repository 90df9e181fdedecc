// The ground station's process core (groundstation/service/process.hpp) with an in-memory CAN
// bus and real Cyclone DDS kept inside this process: operator commands and their answers, KILL on
// the bus, motion capture in, telemetry and events out. Each test case has its own domain id
// (122-126, 129, 130, 132-136); every wait is bounded.
#include "groundstation/service/process.hpp"

#include <array>
#include <catch2/catch.hpp>
#include <chrono>
#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "groundstation/dds/event_detail.hpp"
#include "groundstation/dds/mocap_conversion.hpp"
#include "groundstation/dds/telemetry_conversion.hpp"
#include "groundstation/service/status_view.hpp"

using namespace std::chrono_literals;
using gs::service::Process;

namespace {

constexpr auto kWait = 5s;

gs::runtime::GroundStationConfig keyed_config() {
  gs::runtime::GroundStationConfig c;
  for (const pa::VehicleId v : pa::kActVehicles) {
    gs::link::VehicleKey key{v, {}};
    key.key.fill(static_cast<std::uint8_t>(0x30 + v.node()));
    c.link.keys.push_back(key);
  }
  return c;
}

// The ground station's process and an operator's console on one domain.
struct Rig {
  explicit Rig(dds_domainid_t id, const gs::service::ProcessConfig& process = {})
      : domain(id, gs::dds::in_process_config()),
        station_side(domain),
        console_side(domain),
        process(bus, station_side, keyed_config(), process),
        commands(console_side),
        events(console_side) {
    REQUIRE(commands.wait_for_readers(1, kWait));
    REQUIRE(events.wait_for_writers(1, kWait));
  }

  // Any `kind`: a peer can send any value.
  void send(std::uint8_t kind, std::uint8_t target, std::uint32_t sequence_number) {
    gs::dds::OperatorCommand c{};
    c.kind = kind;
    c.target = target;
    c.sequence_number = sequence_number;
    commands.write(c);
  }

  // The vehicles' LINK_SESSION frames, as after their boot: the link signs frames to them from then on.
  void hear_vehicles() {
    for (const pa::VehicleId v : pa::kActVehicles) {
      pa::proto::Frame f;
      REQUIRE(pa::proto::encode(pa::proto::LinkSession{0x1000u + v.node(), 0}, v.node(), f));
      process.on_frame(f, now_s);
    }
  }

  // Steps until an answer to `sequence_number` arrives (or the wait ends), then a few more steps
  // in which a second answer would show up; every answer to it seen so far.
  std::vector<gs::dds::Event> answers_to(std::uint32_t sequence_number) {
    const auto end = std::chrono::steady_clock::now() + kWait;
    int more_steps = 5;
    while (more_steps > 0 && std::chrono::steady_clock::now() < end) {
      process.step(now_s);
      now_s += 0.005;
      collect(10ms);
      if (!of(sequence_number).empty()) --more_steps;
    }
    return of(sequence_number);
  }

  void collect(std::chrono::nanoseconds wait) {
    for (const gs::dds::Event* e = events.wait_take(wait); e != nullptr; e = events.take()) {
      if (e->kind == gs::dds::event_kind::kCommandAccepted || e->kind == gs::dds::event_kind::kCommandRefused)
        answers.push_back(*e);
      if (e->kind == gs::dds::event_kind::kAttempt) attempts.push_back(*e);
    }
  }

  std::vector<gs::dds::Event> of(std::uint32_t sequence_number) const {
    const std::string prefix = gs::service::answer_prefix(sequence_number) + " ";
    std::vector<gs::dds::Event> found;
    for (const gs::dds::Event& e : answers)
      if (std::strncmp(e.detail, prefix.c_str(), prefix.size()) == 0) found.push_back(e);
    return found;
  }

  std::vector<pa::proto::Message> sent_of_type(pa::proto::Type type) {
    std::vector<pa::proto::Message> out;
    for (const pa::proto::Frame& f : bus.take()) {
      pa::proto::Message m;
      if (pa::proto::decode(f, m) == pa::proto::DecodeStatus::ok && m.type == type) out.push_back(m);
    }
    return out;
  }

  gs::link::InMemoryFrameBus bus;
  gs::dds::Domain domain;
  gs::dds::Participant station_side;
  gs::dds::Participant console_side;
  Process process;
  gs::dds::Writer<gs::dds::OperatorCommand> commands;
  gs::dds::Reader<gs::dds::Event> events;
  double now_s = 10.0;
  std::vector<gs::dds::Event> answers;   // every answer seen, oldest first
  std::vector<gs::dds::Event> attempts;  // every attempt event seen, oldest first
};

}  // namespace

TEST_CASE("An operator command gets exactly one answer naming its sequence number; a repeat is refused") {
  Rig rig(122);
  rig.send(gs::dds::command_kind::kTakeOff, 0, 17);
  const std::vector<gs::dds::Event> first = rig.answers_to(17);
  REQUIRE(first.size() == 1);
  CHECK(first[0].kind == gs::dds::event_kind::kCommandAccepted);
  CHECK(std::string(first[0].detail) == "command 17: take-off requested");

  rig.send(gs::dds::command_kind::kLand, 0, 17);
  const std::vector<gs::dds::Event> both = rig.answers_to(17);
  REQUIRE(both.size() == 2);
  CHECK(both[1].kind == gs::dds::event_kind::kCommandRefused);
  CHECK(std::string(both[1].detail).find("acted on already") != std::string::npos);

  rig.send(gs::dds::command_kind::kLand, 0, 18);
  const std::vector<gs::dds::Event> next = rig.answers_to(18);
  REQUIRE(next.size() == 1);
  CHECK(next[0].kind == gs::dds::event_kind::kCommandAccepted);
  CHECK(rig.process.counters().commands_accepted == 2);
  CHECK(rig.process.counters().commands_refused == 1);
}

TEST_CASE("An accepted throw begins an attempt: its event names the thrower, a refused one has none") {
  Rig rig(130);
  rig.send(gs::dds::command_kind::kThrow, 2, 7);
  const std::vector<gs::dds::Event> answer = rig.answers_to(7);
  REQUIRE(answer.size() == 1);
  CHECK(answer[0].kind == gs::dds::event_kind::kCommandAccepted);
  REQUIRE(rig.attempts.size() == 1);
  CHECK(rig.attempts[0].vehicle == 2);  // what hil run hands the pole up to
  // and where it waits for the pole: vehicle 2 throws back from where vehicle 1's throws come down
  const std::optional<Eigen::Vector3d> origin = gs::dds::attempt_event_origin(rig.attempts[0].detail);
  REQUIRE(origin);
  CHECK(std::string(rig.attempts[0].detail).rfind("attempt 1, pole at ", 0) == 0);
  CHECK(origin->z() == Approx(2.0));
  CHECK(origin->head<2>().norm() > 1.0);

  rig.send(gs::dds::command_kind::kThrow, 1, 8);  // an attempt is running
  const std::vector<gs::dds::Event> refused = rig.answers_to(8);
  REQUIRE(refused.size() == 1);
  CHECK(refused[0].kind == gs::dds::event_kind::kCommandRefused);
  CHECK(rig.attempts.size() == 1);
}

TEST_CASE(
    "KILL reaches the bus as KILL frames, to one vehicle or both, even with a repeated sequence number") {
  Rig rig(123);
  rig.hear_vehicles();
  rig.bus.take();
  rig.send(gs::dds::command_kind::kKill, 2, 5);
  REQUIRE(rig.answers_to(5).size() == 1);
  std::vector<pa::proto::Message> kills = rig.sent_of_type(pa::proto::Type::kill);
  REQUIRE_FALSE(kills.empty());
  for (const pa::proto::Message& m : kills) {
    CHECK(m.node == 2);
    CHECK(m.kill.reason == pa::proto::KillReason::operator_request);
  }

  // The same sequence number again: a KILL is never refused as a repeat.
  rig.send(gs::dds::command_kind::kKill, 0, 5);
  const std::vector<gs::dds::Event> both = rig.answers_to(5);
  REQUIRE(both.size() == 2);
  CHECK(both[1].kind == gs::dds::event_kind::kCommandAccepted);
  kills = rig.sent_of_type(pa::proto::Type::kill);
  bool to_vehicle[2] = {false, false};
  for (const pa::proto::Message& m : kills) {
    REQUIRE(pa::is_act_vehicle(pa::VehicleId(m.node)));
    to_vehicle[pa::act_slot(pa::VehicleId(m.node))] = true;
  }
  CHECK(to_vehicle[0]);
  CHECK(to_vehicle[1]);
  CHECK(rig.process.counters().kills == 2);
}

TEST_CASE("Unknown commands and malformed targets are refused with a reason, never acted on") {
  Rig rig(124);
  rig.hear_vehicles();  // so that a KILL acted on would reach the bus
  rig.bus.take();
  rig.send(99, 0, 1);
  rig.send(gs::dds::command_kind::kThrow, 9, 2);
  rig.send(gs::dds::command_kind::kTakeOff, 1, 3);  // take-off acts on both vehicles only
  rig.send(gs::dds::command_kind::kKill, 200, 4);
  const std::vector<gs::dds::Event> unknown = rig.answers_to(1);
  REQUIRE(unknown.size() == 1);
  CHECK(unknown[0].kind == gs::dds::event_kind::kCommandRefused);
  CHECK(std::string(unknown[0].detail).find("unknown") != std::string::npos);
  for (std::uint32_t n = 2; n <= 4; ++n) {
    const std::vector<gs::dds::Event> a = rig.answers_to(n);
    REQUIRE(a.size() == 1);
    CHECK(a[0].kind == gs::dds::event_kind::kCommandRefused);
  }
  CHECK(rig.process.counters().commands_refused == 4);
  CHECK(rig.process.counters().kills == 0);
  CHECK(rig.sent_of_type(pa::proto::Type::kill).empty());
}

namespace {

// Steps the rig until `frames` motion-capture frames were taken (or the wait ends).
void step_until_mocap(Rig& rig, std::uint64_t frames) {
  const auto end = std::chrono::steady_clock::now() + kWait;
  while (rig.process.counters().mocap_frames < frames && std::chrono::steady_clock::now() < end) {
    rig.process.step(rig.now_s);
    rig.now_s += 0.005;
  }
}

gs::estimation::MocapFrame both_vehicles() {
  gs::estimation::MocapFrame frame;
  gs::estimation::MocapPose pose;
  pose.p_m = Eigen::Vector3d(-1.0, 0.0, 0.1);
  frame.vehicle[0] = pose;
  pose.p_m = Eigen::Vector3d(1.0, 0.0, 0.1);
  frame.vehicle[1] = pose;
  return frame;
}

}  // namespace

TEST_CASE("Motion-capture frames published on rt/poses reach the runtime's estimator") {
  Rig rig(125);
  gs::dds::Writer<gs::dds::NamedPoseArray> mocap(rig.console_side);
  REQUIRE(mocap.wait_for_readers(1, kWait));

  gs::dds::MocapMessage message;
  gs::dds::mocap_frame_to_dds(both_vehicles(), gs::dds::to_nanoseconds(rig.now_s), gs::dds::MocapBodyNames{},
                              message);
  REQUIRE(message.add("wand", gs::estimation::MocapPose{}));
  mocap.write(message.message());

  step_until_mocap(rig, 1);
  CHECK(rig.process.counters().mocap_frames == 1);
  CHECK(rig.process.counters().mocap_unknown_bodies == 1);
  CHECK(rig.process.ground_station().estimator().vehicle_initialised(pa::kVehicle1));
  CHECK(rig.process.ground_station().estimator().vehicle_initialised(pa::kVehicle2));
  CHECK(rig.process.summary().find("body 'wand' is none of vehicle 1 ('vehicle1')") != std::string::npos);
}

TEST_CASE("A stamp on the system clock is placed on the ground clock less the capture latency") {
  gs::service::ProcessConfig config;
  config.mocap.names = {"cf1", "cf2", "stick"};
  config.mocap.latency_s = 0.008;
  Rig rig(132, config);
  // The system clock 1.7e9 s ahead of the ground clock, as CLOCK_REALTIME is of CLOCK_MONOTONIC.
  const std::int64_t offset_ns = 1'700'000'000'000'000'000;
  rig.process.set_stamp_offset(offset_ns);
  gs::dds::Writer<gs::dds::NamedPoseArray> mocap(rig.console_side);
  REQUIRE(mocap.wait_for_readers(1, kWait));

  // Stamped 3 ms before the step that takes it: the node's clock reads ground time + offset.
  const double stamp_ground_s = rig.now_s - 0.003;
  gs::dds::MocapMessage message;
  gs::dds::mocap_frame_to_dds(both_vehicles(), offset_ns + gs::dds::to_nanoseconds(stamp_ground_s),
                              config.mocap.names, message);
  mocap.write(message.message());
  step_until_mocap(rig, 1);
  REQUIRE(rig.process.counters().mocap_frames == 1);
  CHECK(rig.process.counters().mocap_unknown_bodies == 0);
  CHECK(rig.process.counters().mocap_implausible_stamps == 0);
  CHECK(rig.process.ground_station().estimator().vehicle_initialised(pa::kVehicle2));
  // The estimator took the frame at its capture: the stamp on the ground clock less 8 ms.
  CHECK(rig.process.ground_station().estimator().time() == Approx(stamp_ground_s - 0.008).margin(1e-6));
  CHECK(rig.process.counters().mocap_delay_max_s >= 0.003 - 1e-6);

  // A stamp an hour off (the hosts' clocks not synchronised): counted, timed by its arrival.
  gs::dds::mocap_frame_to_dds(both_vehicles(), offset_ns + gs::dds::to_nanoseconds(rig.now_s + 3600.0),
                              config.mocap.names, message);
  mocap.write(message.message());
  step_until_mocap(rig, 2);
  REQUIRE(rig.process.counters().mocap_frames == 2);
  CHECK(rig.process.counters().mocap_implausible_stamps == 1);
  CHECK(rig.process.ground_station().estimator().time() < rig.now_s);
  CHECK(rig.process.summary().find("synchronised") != std::string::npos);
}

TEST_CASE("Malformed pose arrays are counted and never crash the process") {
  Rig rig(133);
  gs::dds::Writer<gs::dds::NamedPoseArray> mocap(rig.console_side);
  REQUIRE(mocap.wait_for_readers(1, kWait));
  const double nan = std::numeric_limits<double>::quiet_NaN();

  gs::dds::MocapMessage message;
  // NaN orientation (a position-only body), a zero quaternion, a NaN position, a duplicate, an
  // overlong name; then an empty array.
  message.clear(gs::dds::to_nanoseconds(rig.now_s));
  REQUIRE(message.add("vehicle1", gs::estimation::MocapPose{}));
  message.back().pose.orientation = {nan, nan, nan, nan};
  REQUIRE(message.add("vehicle2", gs::estimation::MocapPose{}));
  message.back().pose.orientation = {0.0, 0.0, 0.0, 0.0};
  REQUIRE(message.add("pole", gs::estimation::MocapPose{}));
  message.back().pose.position.x = nan;
  REQUIRE(message.add("pole", gs::estimation::MocapPose{}));
  REQUIRE(message.add(std::string(200, 'z'), gs::estimation::MocapPose{}));
  mocap.write(message.message());
  step_until_mocap(rig, 1);
  message.clear(gs::dds::to_nanoseconds(rig.now_s));
  mocap.write(message.message());
  step_until_mocap(rig, 2);

  const gs::service::ProcessCounters& c = rig.process.counters();
  CHECK(c.mocap_frames == 2);
  CHECK(c.mocap_invalid_poses == 3);
  CHECK(c.mocap_duplicate_bodies == 1);
  CHECK(c.mocap_unknown_bodies == 1);
  CHECK_FALSE(rig.process.ground_station().estimator().vehicle_initialised(pa::kVehicle1));
  CHECK_FALSE(rig.process.ground_station().estimator().vehicle_initialised(pa::kVehicle2));
}

namespace {

// A process on the plant's clock (groundstation run --hil-clock) and the plant's motion capture.
struct PlantClockRig {
  explicit PlantClockRig(dds_domainid_t id) : rig(id, config()), mocap(rig.console_side) {
    REQUIRE(mocap.wait_for_readers(1, kWait));
  }
  static gs::service::ProcessConfig config() { return {}; }
  // Frames of both vehicles stamped first_s, first_s + 5 ms, ... (the plant's time).
  void publish(int count, double first_s) {
    for (int n = 0; n < count; ++n) {
      gs::dds::mocap_frame_to_dds(both_vehicles(), gs::dds::to_nanoseconds(first_s + 0.005 * n),
                                  gs::dds::MocapBodyNames{}, message);
      mocap.write(message.message());
    }
  }
  Rig rig;
  gs::dds::Writer<gs::dds::NamedPoseArray> mocap;
  gs::dds::MocapMessage message;
};

}  // namespace

TEST_CASE("On the plant's clock a burst of frames is met by its newest") {
  // The plant stepped on without the ground station (a restart, a release): frames piled up
  // unread, and the reader kept the newest. Its stamp, within the clock's step, says the clock's
  // five frames are in: no wait for the four it replaced.
  PlantClockRig plant(135);
  plant.publish(5, 0.005);
  const auto start = std::chrono::steady_clock::now();
  CHECK(plant.rig.process.await_mocap(5, 0.025, kWait));
  CHECK(std::chrono::steady_clock::now() - start < 1s);
  CHECK(plant.rig.process.counters().mocap_frames == 1);
  CHECK(plant.rig.process.await_mocap(5, 0.026, 50ms));  // the next step: no new frame, none awaited
}

TEST_CASE("On the plant's clock a frame newer than the clock ends the wait, and is counted beyond it") {
  // A ground station started while the plant ran on without it: the plant has counted 100
  // frames, this one saw none of them, and the frames waiting are from after the clock it reads.
  PlantClockRig plant(136);
  Process& process = plant.rig.process;
  plant.publish(3, 0.505);
  const auto start = std::chrono::steady_clock::now();
  CHECK(process.await_mocap(100, 0.500, kWait));
  CHECK(std::chrono::steady_clock::now() - start < 1s);
  // The plant's next clocks count those three: no wait for frames already in.
  CHECK(process.await_mocap(103, 0.515, 50ms));
  CHECK(process.counters().mocap_frames <= 3);
  plant.publish(1, 0.520);
  CHECK(process.await_mocap(104, 0.520, kWait));
  CHECK(process.await_mocap(104, 0.521, 50ms));
}

TEST_CASE("On the plant's clock the process waits for the frames the plant counted") {
  Rig rig(134);
  gs::dds::Writer<gs::dds::NamedPoseArray> mocap(rig.console_side);
  REQUIRE(mocap.wait_for_readers(1, kWait));
  gs::dds::MocapMessage message;
  gs::dds::mocap_frame_to_dds(both_vehicles(), gs::dds::to_nanoseconds(0.010), gs::dds::MocapBodyNames{},
                              message);
  mocap.write(message.message());
  CHECK(rig.process.await_mocap(1, 0.010, kWait));
  CHECK(rig.process.counters().mocap_frames == 1);
  // The second frame never comes: a bounded wait, then the count takes the plant's, so that one
  // lost frame costs one wait, not one per step after it.
  CHECK_FALSE(rig.process.await_mocap(2, 0.015, 50ms));
  const auto start = std::chrono::steady_clock::now();
  CHECK(rig.process.await_mocap(2, 0.020, kWait));
  CHECK(std::chrono::steady_clock::now() - start < 10ms);
}

TEST_CASE("Telemetry is published at its rate, for both vehicles and the pole") {
  gs::service::ProcessConfig config;
  config.telemetry_period_s = 1.0 / 32.0;  // exact in binary: the steps below land on it
  Rig rig(126, config);
  // Stamped with ROS time: the ground clock plus the system clock's offset.
  constexpr std::int64_t kOffset_ns = 1'796'600'000'000'000'000;
  rig.process.set_stamp_offset(kOffset_ns);
  std::array<gs::dds::Reader<gs::dds::VehicleTelemetry>, 2> vehicles{
      gs::dds::Reader<gs::dds::VehicleTelemetry>(rig.console_side,
                                                 gs::dds::vehicle_telemetry_topic(pa::kVehicle1).c_str()),
      gs::dds::Reader<gs::dds::VehicleTelemetry>(rig.console_side,
                                                 gs::dds::vehicle_telemetry_topic(pa::kVehicle2).c_str())};
  gs::dds::Reader<gs::dds::PoleTelemetry> pole(rig.console_side);
  for (const auto& reader : vehicles) REQUIRE(reader.wait_for_writers(1, kWait));
  REQUIRE(pole.wait_for_writers(1, kWait));

  // 64 steps of 1/256 s: telemetry at steps 0, 8, ..., 56.
  for (int i = 0; i < 64; ++i) rig.process.step(10.0 + i / 256.0);
  CHECK(rig.process.counters().telemetry_published == 8 * 3);

  const std::int64_t last_ns = gs::dds::to_nanoseconds(10.0 + 56 / 256.0) + kOffset_ns;
  for (const pa::VehicleId v : pa::kActVehicles) {
    // Keep last 1: the newest sample of each vehicle, on its own topic.
    const gs::dds::VehicleTelemetry* t = vehicles[pa::act_slot(v)].wait_take(kWait);
    REQUIRE(t != nullptr);
    CHECK(t->vehicle == v.node());
    CHECK(t->link == gs::dds::link_state::kUnheard);  // no vehicle on the bus
    CHECK(gs::dds::stamp_nanoseconds(t->stamp) == last_ns);
  }
  const gs::dds::PoleTelemetry* p = pole.wait_take(kWait);
  REQUIRE(p != nullptr);
  CHECK(gs::dds::stamp_nanoseconds(p->stamp) == last_ns);
  CHECK_FALSE(p->estimate_valid);
  CHECK_FALSE(p->catch_predicted);
}

TEST_CASE("A vehicle heard, then silent, is announced back and then lost; its failsafe is announced") {
  Rig rig(129);
  gs::dds::Reader<gs::dds::Event> events(rig.console_side);
  REQUIRE(events.wait_for_writers(1, kWait));
  pa::proto::Frame heartbeat;
  REQUIRE(pa::proto::encode(pa::proto::VehicleHeartbeat{500, pa::proto::Mode::failsafe_hover, 0, 0,
                                                        pa::proto::FailsafeReason::heartbeat_lost, 0},
                            2, heartbeat));
  rig.process.on_frame(heartbeat, rig.now_s);
  rig.process.step(rig.now_s);
  rig.process.step(rig.now_s + 1.0);  // past the link's vehicle timeout (0.3 s)

  std::vector<std::string> lines;
  for (const gs::dds::Event* e = events.wait_take(kWait); e != nullptr; e = events.wait_take(100ms))
    if (e->vehicle == 2) lines.push_back(gs::service::event_kind_name(e->kind) + ": " + e->detail);
  REQUIRE(lines.size() == 3);
  CHECK(lines[0] == "vehicle back: first heartbeat");
  CHECK(lines[1].rfind("failsafe: the vehicle reports failsafe reason", 0) == 0);
  CHECK(lines[2] == "vehicle lost: no heartbeat");
}

TEST_CASE("Operator command names round-trip, and the answer prefix is what op looks for") {
  for (const char* name : {"take-off", "land", "abort", "throw", "kill"}) {
    const std::optional<std::uint8_t> kind = gs::service::command_from_name(name);
    REQUIRE(kind);
    CHECK(gs::service::command_name(*kind) == name);
  }
  CHECK_FALSE(gs::service::command_from_name("takeoff"));
  CHECK(gs::service::answer_prefix(42) == "command 42:");
}

TEST_CASE("A pole_wanted detail round-trips, and any other text says nothing") {
  for (const bool waiting : {true, false})
    CHECK(gs::dds::pole_wanted(gs::dds::pole_wanted_detail(waiting)) == waiting);
  for (const char* other : {"", "Waiting", "waiting ", "not", "attempt 3, pole at 0.000 0.000 2.000"})
    CHECK_FALSE(gs::dds::pole_wanted(other).has_value());
}

TEST_CASE("A task change names its tasks and reason, and what the vehicle answered when a command failed") {
  using gs::mission::Reason;
  using gs::mission::Task;
  CHECK(gs::dds::task_change_detail(Task::retreat, Task::hover, Reason::clear_of_pole) ==
        "retreat -> hover (clear_of_pole)");
  CHECK(gs::dds::task_change_detail(Task::arming, Task::parked, Reason::arm_failed,
                                    "ARM refused: imu_unhealthy") ==
        "arming -> parked (arm_failed): ARM refused: imu_unhealthy");
}
