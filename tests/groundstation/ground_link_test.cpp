// The ground link (groundstation/link/ground_link.hpp) against the real firmware (fw::Vehicle)
// wherever the vehicle takes part: the frames it sends are carried by an in-memory bus and a
// simulated radio (hil::RadioBridge) to firmware vehicles ticking at 1 kHz on their own clocks,
// and their frames back to the link. Time is simulated; nothing here reads a wall clock.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <functional>
#include <limits>
#include <memory>
#include <new>
#include <random>
#include <stdexcept>
#include <vector>

#include "fw/vehicle.hpp"
#include "groundstation/link/frame_bus.hpp"
#include "groundstation/link/ground_link.hpp"
#include "hil/radio/radio_bridge.hpp"

// Every allocation in this executable is counted, so that a test can show a code path does not
// allocate (the link's on_frame under a flood).
namespace {
std::uint64_t g_allocations = 0;
}  // namespace

// (Every form is replaced, so that a sanitizer's own operators never free what these allocated.)
namespace {
void* counted_allocation(std::size_t size) noexcept {
  ++g_allocations;
  return std::malloc(size == 0 ? 1 : size);
}
void* counted_or_throw(std::size_t size) {
  if (void* p = counted_allocation(size)) return p;
  throw std::bad_alloc();
}
}  // namespace

void* operator new(std::size_t size) { return counted_or_throw(size); }
void* operator new[](std::size_t size) { return counted_or_throw(size); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept { return counted_allocation(size); }
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept { return counted_allocation(size); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }

using namespace pa::proto;
using gs::link::CommandHandle;
using gs::link::CommandState;
using gs::link::GroundLink;
using gs::link::GroundLinkConfig;
using gs::link::InMemoryFrameBus;

namespace {

constexpr double kT0 = 1000.0;  // the ground clock when a rig starts
constexpr float kG = 9.81f;
constexpr double kVehicleWrap_s = 4294.967296;  // the vehicle's uint32 microsecond clock
constexpr std::uint8_t kBothNodes[] = {1, 2};

Message decoded(const Frame& f) {
  Message m;
  REQUIRE(decode(f, m) == DecodeStatus::ok);
  return m;
}

template <class M>
Frame encoded(const M& m, std::uint8_t node) {
  Frame f;
  REQUIRE(encode(m, node, f));
  return f;
}

// Each vehicle's link key, as provisioned on it and given to the link.
pa::auth::Key test_key(std::uint8_t node) {
  pa::auth::Key k;
  for (std::size_t i = 0; i < k.size(); ++i) k[i] = static_cast<std::uint8_t>(node * 31 + i + 1);
  return k;
}

GroundLinkConfig keyed(GroundLinkConfig config, const std::vector<std::uint8_t>& nodes) {
  for (std::uint8_t n : nodes) config.keys.push_back({pa::VehicleId(n), test_key(n)});
  return config;
}

// One firmware vehicle resting level on the floor, behind its radio.
struct SimVehicle {
  fw::VehicleConfig config;
  std::unique_ptr<fw::Vehicle> firmware;
  hil::RadioBridge radio;
  double clock_offset_s;  // ground time = vehicle time + clock_offset_s
  bool powered = true;
  float accel_z_mps2 = kG;  // what its IMU reads on the body z-axis
  // Return true to lose a frame (decoded) on its way up to the vehicle or down to the ground.
  std::function<bool(const Message&)> drop_uplink;
  std::function<bool(const Message&)> drop_downlink;

  SimVehicle(std::uint8_t node, double offset_s, const hil::RadioConfig& radio_config)
      : radio(radio_config), clock_offset_s(offset_s) {
    config.link.vehicle = pa::VehicleId(node);
    config.link.key = test_key(node);
    config.link.session_nonce = 1000u + node;
    firmware = std::make_unique<fw::Vehicle>(config);
  }
  std::uint8_t node() const { return config.link.vehicle.node(); }
  std::uint32_t clock_us(double ground_s) const {
    return static_cast<std::uint32_t>(
        static_cast<std::uint64_t>(std::llround((ground_s - clock_offset_s) * 1e6)));
  }
  // The vehicle restarts: a new firmware whose clock starts at zero now, in a new link session.
  void reboot(double ground_s) {
    ++config.link.session_nonce;
    firmware = std::make_unique<fw::Vehicle>(config);
    clock_offset_s = ground_s;
  }
};

struct Sent {
  double t_s;
  Frame frame;
};

std::vector<pa::VehicleId> ids_of(const std::vector<std::uint8_t>& nodes) {
  std::vector<pa::VehicleId> ids;
  for (std::uint8_t n : nodes) ids.emplace_back(n);
  return ids;
}

struct Rig {
  InMemoryFrameBus bus;
  GroundLink link;
  std::vector<std::unique_ptr<SimVehicle>> vehicles;
  long step_count = 0;
  std::vector<Sent> uplink;  // every frame the link sent, when the bus carried it

  explicit Rig(std::vector<std::uint8_t> nodes, const hil::RadioConfig& radio = {0.0, 0.0, 0.0, 1},
               std::vector<double> clock_offsets_s = {}, const GroundLinkConfig& config = {})
      : link(bus, ids_of(nodes), keyed(config, nodes)) {
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      hil::RadioConfig r = radio;
      r.seed = radio.seed + static_cast<std::uint32_t>(i);
      const double offset = i < clock_offsets_s.size() ? clock_offsets_s[i] : kT0 - 5.0;
      vehicles.push_back(std::make_unique<SimVehicle>(nodes[i], offset, r));
    }
  }
  double t() const { return kT0 + static_cast<double>(step_count) * 1e-3; }
  SimVehicle& vehicle(std::size_t i = 0) { return *vehicles[i]; }

  // One millisecond: the link's tick, the ground bus onto every radio, then each vehicle reads
  // what arrived, runs its 1 kHz tick and sends; the ground reads what arrived.
  void step() {
    const double now = t();
    link.tick(now);
    for (const Frame& f : bus.take()) {
      uplink.push_back({now, f});
      for (auto& v : vehicles)
        if (!(v->drop_uplink && v->drop_uplink(decoded(f)))) v->radio.offer(hil::Side::ground, f, now);
    }
    for (auto& v : vehicles) {
      Frame f;
      if (v->powered) {
        while (v->radio.deliver(hil::Side::vehicle, now, f)) v->firmware->on_frame(f, v->clock_us(now));
        fw::ImuSample imu;
        imu.t_us = v->clock_us(now);
        imu.accel_mps2 = {0.0f, 0.0f, v->accel_z_mps2};
        v->firmware->tick(imu);
        while (v->firmware->pop_tx(f))
          if (!(v->drop_downlink && v->drop_downlink(decoded(f)))) v->radio.offer(hil::Side::vehicle, f, now);
      } else {
        while (v->radio.deliver(hil::Side::vehicle, now, f)) {
        }
      }
      while (v->radio.deliver(hil::Side::ground, now, f)) link.on_frame(f, now);
    }
    ++step_count;
  }
  void run(double duration_s) {
    const long n = std::lround(duration_s * 1e3);
    for (long i = 0; i < n; ++i) step();
  }
  // Steps until `done` holds (true) or max_s has passed (false).
  bool run_until(const std::function<bool()>& done, double max_s) {
    const long n = std::lround(max_s * 1e3);
    for (long i = 0; i < n; ++i) {
      if (done()) return true;
      step();
    }
    return done();
  }
  std::vector<Sent> sent_of_type(Type type) const {
    std::vector<Sent> out;
    for (const Sent& s : uplink)
      if (id_type(s.frame.id) == static_cast<std::uint8_t>(type)) out.push_back(s);
    return out;
  }
  CommandState wait_for(const CommandHandle& h, double max_s = 1.0) {
    run_until([&] { return link.command_state(h) != CommandState::pending; }, max_s);
    return link.command_state(h);
  }
};

gs::model::VehicleInput input(double thrust_mps2, Eigen::Vector3d rates_radps = Eigen::Vector3d::Zero()) {
  gs::model::VehicleInput u;
  u.a_q_mps2 = thrust_mps2;
  u.omega_radps = rates_radps;
  return u;
}

bool is_command_ack(const Message& m) { return m.type == Type::command_ack; }

}  // namespace

TEST_CASE("the link is built for a list of distinct vehicle nodes 1..14 and a sane configuration") {
  InMemoryFrameBus bus;
  CHECK_NOTHROW(GroundLink(bus, ids_of({1, 2, 14}), keyed({}, {1, 2, 14})));
  CHECK_THROWS_AS(GroundLink(bus, ids_of({}), keyed({}, {})), std::invalid_argument);
  CHECK_THROWS_AS(GroundLink(bus, ids_of({0}), keyed({}, {0})), std::invalid_argument);
  CHECK_THROWS_AS(GroundLink(bus, ids_of({15}), keyed({}, {15})), std::invalid_argument);
  CHECK_THROWS_AS(GroundLink(bus, ids_of({3, 4, 3}), keyed({}, {3, 4})), std::invalid_argument);
  // Every vehicle needs its key, and a key that is all zeros (or erased flash) is none.
  CHECK_THROWS_AS(GroundLink(bus, ids_of({1, 2}), keyed({}, {1})), std::invalid_argument);
  GroundLinkConfig unkeyed;
  unkeyed.keys.push_back({pa::VehicleId(1), pa::auth::Key{}});
  CHECK_THROWS_AS(GroundLink(bus, ids_of({1}), unkeyed), std::invalid_argument);
  GroundLinkConfig bad = keyed({}, {1});
  bad.command_attempts = 0;
  CHECK_THROWS_AS(GroundLink(bus, ids_of({1}), bad), std::invalid_argument);
  bad = keyed({}, {1});
  bad.heartbeat_period_s = 0.0;
  CHECK_THROWS_AS(GroundLink(bus, ids_of({1}), bad), std::invalid_argument);
  bad = keyed({}, {1});
  bad.link_quality_window_s = 60.0;  // more heartbeats than the link keeps
  CHECK_THROWS_AS(GroundLink(bus, ids_of({1}), bad), std::invalid_argument);

  GroundLink link(bus, ids_of({2, 5}), keyed({}, {2, 5}));
  CHECK(link.status(pa::VehicleId(5)).vehicle == pa::VehicleId(5));
  CHECK(link.status(pa::VehicleId(5)).lost);
  CHECK_FALSE(link.status(pa::VehicleId(5)).heard);
  CHECK_THROWS_AS(link.status(pa::VehicleId(3)), std::out_of_range);
  CHECK_THROWS_AS(link.send_setpoint(pa::VehicleId(3), input(0.0)), std::out_of_range);
  CHECK_THROWS_AS(link.send_command(pa::VehicleId(3), CommandCode::arm, 0, 0.0), std::out_of_range);
  CHECK_THROWS_AS(link.send_kill(pa::VehicleId(3), KillReason::operator_request), std::out_of_range);
  CHECK_THROWS_AS(link.ground_time(pa::VehicleId(3), 0), std::out_of_range);
  CHECK(bus.pending() == 0);  // nothing went out for the unknown node
}

TEST_CASE(
    "ground heartbeats go out every 20 ms with the session, and the firmware binds it and counts them live") {
  GroundLinkConfig config;
  config.session = 0x5A17;
  Rig rig({1}, {0.0, 0.0, 0.0, 1}, {}, config);
  rig.run(1.0);

  // The first heartbeat, and the first TIMESYNC request (once the vehicle's heartbeat is heard),
  // go before its LINK_SESSION (6 ms after its boot) is heard: unsigned, they are not sent.
  const std::vector<Sent> hb = rig.sent_of_type(Type::gs_heartbeat);
  REQUIRE(hb.size() == 49);
  CHECK(rig.link.counters().unsigned_dropped == 2);
  CHECK(rig.link.counters().sessions_started == 1);
  for (std::size_t i = 0; i < hb.size(); ++i) {
    const Message m = decoded(hb[i].frame);
    CHECK(m.node == 1);
    CHECK(m.gs_heartbeat.session_token == 0x5A17);
    CHECK(m.gs_heartbeat.seq == static_cast<std::uint8_t>(i + 1));
    CHECK(m.gs_heartbeat.ground_time_ms == GroundLink::ground_time_ms(hb[i].t_s));
    if (i > 0) CHECK(hb[i].t_s - hb[i - 1].t_s == Approx(0.02).margin(1e-9));
  }
  const fw::Vehicle& vehicle = *rig.vehicle().firmware;
  CHECK(vehicle.link().has_session());
  CHECK(vehicle.link().session_token() == 0x5A17);
  CHECK(vehicle.link().heartbeat_live(rig.vehicle().clock_us(rig.t())));
  CHECK(vehicle.link().counters().stale_sequence == 0);
  CHECK(vehicle.rx_rejected() == 0);  // every frame came with its valid AUTH
  CHECK(vehicle.guard().last_counter() > 49);
  // ... and says so in its own heartbeat.
  const auto& status = rig.link.status(pa::VehicleId(1));
  CHECK(status.heard);
  CHECK_FALSE(status.lost);
  CHECK((status.flags & kFlagGroundHeartbeatOk) != 0);
  CHECK(status.mode == Mode::disarmed);
}

TEST_CASE(
    "ARM through the link: a real vehicle accepts it with a zero-thrust setpoint and a live heartbeat") {
  Rig rig({1});
  rig.run(0.1);
  rig.link.send_setpoint(pa::VehicleId(1), input(0.0));
  rig.run(0.01);
  const CommandHandle h = rig.link.send_command(pa::VehicleId(1), CommandCode::arm, 0, rig.t());
  CHECK(h.vehicle == pa::kVehicle1);
  CHECK(rig.link.command_state(h) == CommandState::pending);
  CHECK(rig.wait_for(h) == CommandState::accepted);
  const auto outcome = rig.link.command_outcome(h);
  CHECK(outcome.attempts == 1);
  CHECK_FALSE(outcome.inferred);
  CHECK(outcome.mode == Mode::armed);
  CHECK(rig.vehicle().firmware->mode() == Mode::armed);
  rig.run(0.3);
  CHECK(rig.sent_of_type(Type::command).size() == 1);  // acknowledged: never resent
  CHECK(rig.link.status(pa::VehicleId(1)).mode == Mode::armed);
  CHECK(rig.link.status(pa::VehicleId(1)).armed);
  CHECK(rig.link.counters().stale == 0);
}

TEST_CASE("a refused command reports the vehicle's reason and is not retried") {
  Rig rig({1});
  SECTION("a non-zero setpoint held by the vehicle: thrust_not_zero, until a zero one replaces it") {
    rig.run(0.1);
    rig.link.send_setpoint(pa::VehicleId(1), input(3.0));
    rig.run(0.1);  // no longer fresh, but still the vehicle's latest setpoint
    const CommandHandle h = rig.link.send_command(pa::VehicleId(1), CommandCode::arm, 0, rig.t());
    CHECK(rig.wait_for(h) == CommandState::refused);
    CHECK(rig.link.command_outcome(h).reason == RefuseReason::thrust_not_zero);
    CHECK(rig.vehicle().firmware->mode() == Mode::disarmed);
    rig.run(0.3);
    CHECK(rig.sent_of_type(Type::command).size() == 1);

    rig.link.send_setpoint(pa::VehicleId(1), input(0.0));
    const CommandHandle again = rig.link.send_command(pa::VehicleId(1), CommandCode::arm, 0, rig.t());
    CHECK(again.sequence != h.sequence);
    CHECK(rig.wait_for(again) == CommandState::accepted);
  }
  SECTION("no ground heartbeat ever reached the vehicle: it has no session") {
    rig.vehicle().drop_uplink = [](const Message& m) { return m.type == Type::gs_heartbeat; };
    rig.run(0.1);
    const CommandHandle h = rig.link.send_command(pa::VehicleId(1), CommandCode::arm, 0, rig.t());
    CHECK(rig.wait_for(h) == CommandState::refused);
    CHECK(rig.link.command_outcome(h).reason == RefuseReason::bad_session_token);
  }
  SECTION("LAND on the ground: not_flying") {
    rig.run(0.1);
    const CommandHandle h = rig.link.send_command(pa::VehicleId(1), CommandCode::land, 0, rig.t());
    CHECK(rig.wait_for(h) == CommandState::refused);
    CHECK(rig.link.command_outcome(h).reason == RefuseReason::not_flying);
  }
}

TEST_CASE("an unacknowledged ARM is retried with the same sequence") {
  Rig rig({1});
  rig.run(0.1);
  rig.link.send_setpoint(pa::VehicleId(1), input(0.0));
  int dropped = 0;

  SECTION("the ack was lost: the retry finds the vehicle armed, which the link reports as accepted") {
    rig.vehicle().drop_downlink = [&](const Message& m) { return is_command_ack(m) && dropped++ == 0; };
    const CommandHandle h = rig.link.send_command(pa::VehicleId(1), CommandCode::arm, 0, rig.t());
    CHECK(rig.wait_for(h) == CommandState::accepted);
    const auto outcome = rig.link.command_outcome(h);
    CHECK(outcome.attempts == 2);
    CHECK(outcome.inferred);
    CHECK(outcome.reason == RefuseReason::not_disarmed);  // what the firmware answered the retry
    CHECK(rig.vehicle().firmware->mode() == Mode::armed);
  }
  SECTION("the command was lost: the retry arms the vehicle") {
    rig.vehicle().drop_uplink = [&](const Message& m) { return m.type == Type::command && dropped++ == 0; };
    const CommandHandle h = rig.link.send_command(pa::VehicleId(1), CommandCode::arm, 0, rig.t());
    CHECK(rig.wait_for(h) == CommandState::accepted);
    CHECK(rig.link.command_outcome(h).attempts == 2);
    CHECK_FALSE(rig.link.command_outcome(h).inferred);
    CHECK(rig.vehicle().firmware->mode() == Mode::armed);
  }
  const std::vector<Sent> commands = rig.sent_of_type(Type::command);
  REQUIRE(commands.size() == 2);
  CHECK(commands[1].t_s - commands[0].t_s == Approx(0.05).margin(0.0015));
  CHECK(decoded(commands[0].frame).command.seq == decoded(commands[1].frame).command.seq);
}

TEST_CASE("a COMMAND that never gets through times out after its attempts, its outcome unknown") {
  Rig rig({1});
  rig.vehicle().drop_uplink = [](const Message& m) { return m.type == Type::command; };
  rig.run(0.1);
  const double sent_s = rig.t();
  const CommandHandle h = rig.link.send_command(pa::VehicleId(1), CommandCode::arm, 0, sent_s);
  rig.run_until([&] { return rig.t() >= sent_s + 0.24; }, 1.0);
  CHECK(rig.link.command_state(h) == CommandState::pending);  // 5 attempts, 50 ms apart
  CHECK(rig.wait_for(h) == CommandState::timed_out);
  CHECK(rig.t() - sent_s <= 0.26);
  CHECK(rig.link.command_outcome(h).attempts == 5);
  rig.run(0.5);
  CHECK(rig.sent_of_type(Type::command).size() == 5);
  CHECK(rig.vehicle().firmware->mode() == Mode::disarmed);
}

TEST_CASE("pending commands are bounded per vehicle; a handle the link does not know is unknown") {
  InMemoryFrameBus bus;
  GroundLink link(bus, ids_of({1}), keyed({}, {1}));
  std::vector<CommandHandle> handles;
  for (std::size_t i = 0; i <= GroundLink::kMaxPendingCommands; ++i)
    handles.push_back(link.send_command(pa::VehicleId(1), CommandCode::disarm, 0, 0.0));
  CHECK(link.command_state(handles.front()) == CommandState::timed_out);
  CHECK(link.counters().commands_evicted == 1);
  for (std::size_t i = 1; i < handles.size(); ++i)
    CHECK(link.command_state(handles[i]) == CommandState::pending);
  for (int i = 0; i < 40; ++i) link.send_command(pa::VehicleId(1), CommandCode::disarm, 0, 0.0);
  CHECK(link.command_state(handles.back()) == CommandState::unknown);  // its record was reused
  CHECK(link.command_state(CommandHandle{}) == CommandState::unknown);
  CHECK(link.command_state(CommandHandle{pa::VehicleId(7), 0, 1}) == CommandState::unknown);
}

TEST_CASE(
    "setpoints: the next 4-bit sequence each time, wrapping at 16, and every one fresh for the firmware") {
  Rig rig({1});
  rig.run(0.1);
  std::vector<gs::model::VehicleInput> returned;
  std::vector<std::uint8_t> seqs;
  for (int i = 0; i < 40; ++i) {
    const auto u = rig.link.send_setpoint(pa::VehicleId(1), input(0.0, Eigen::Vector3d(0.01 * i, -0.3, 0.0)));
    // The vehicle reads it in this millisecond and acts on it once its AUTH has been checked: two
    // ticks later, or a few more when a heartbeat or time-sync request is queued before it.
    const std::uint8_t sent_seq = rig.link.status(pa::VehicleId(1)).setpoint_seq_sent;
    const auto acted_on = [&] { return rig.vehicle().firmware->link().setpoint().seq == sent_seq; };
    const double t_sent = rig.t();
    REQUIRE(rig.run_until(acted_on, 0.01));
    CHECK(rig.t() - t_sent <= 0.01);
    const fw::Vehicle& fw = *rig.vehicle().firmware;
    const RateThrust& held = fw.link().setpoint();
    CHECK(fw.link().setpoint_fresh(rig.vehicle().clock_us(rig.t() - 1e-3)));
    // What the link returned is what the vehicle flies, exactly.
    CHECK(u.omega_radps.x() == static_cast<double>(held.rate_radps[0]));
    CHECK(u.omega_radps.y() == static_cast<double>(held.rate_radps[1]));
    CHECK(u.a_q_mps2 == static_cast<double>(held.thrust_mps2));
    seqs.push_back(held.seq);
    rig.run(0.002);
  }
  CHECK(rig.vehicle().firmware->link().counters().stale_sequence == 0);
  for (std::size_t i = 1; i < seqs.size(); ++i) CHECK(seqs[i] == ((seqs[i - 1] + 1) & 0x0F));
  CHECK(rig.link.status(pa::VehicleId(1)).setpoint_seq_sent == seqs.back());
  rig.run(0.05);
  CHECK(rig.link.status(pa::VehicleId(1)).last_setpoint_seq ==
        seqs.back());  // reported back in its heartbeat
}

TEST_CASE("a setpoint comes back as the frame carries it: quantised and clamped") {
  InMemoryFrameBus bus;
  GroundLink link(bus, ids_of({4}), keyed({}, {4}));
  link.on_frame(encoded(LinkSession{1, 0}, 4), 0.0);
  auto u = link.send_setpoint(pa::VehicleId(4), input(9.8149, Eigen::Vector3d(1.0011, -0.0029, 70.0)));
  CHECK(u.a_q_mps2 == Approx(9.81).margin(1e-5));
  CHECK(u.omega_radps.x() == Approx(1.002).margin(1e-5));
  CHECK(u.omega_radps.y() == Approx(-0.002).margin(1e-6));
  CHECK(u.omega_radps.z() == Approx(65.534).margin(1e-3));  // the frame's range
  u = link.send_setpoint(pa::VehicleId(4), input(100.0));
  CHECK(u.a_q_mps2 == Approx(kThrustMax_mps2));
  u = link.send_setpoint(pa::VehicleId(4), input(-3.0));
  CHECK(u.a_q_mps2 == 0.0);
  u = link.send_setpoint(pa::VehicleId(4),
                         input(1e300, Eigen::Vector3d(-1e300, 0, 0)));  // finite but far out
  CHECK(u.a_q_mps2 == Approx(kThrustMax_mps2));
  CHECK(u.omega_radps.x() == Approx(-65.534).margin(1e-3));
  CHECK(bus.pending() == 8);  // each with its AUTH

  CHECK_THROWS_AS(link.send_setpoint(pa::VehicleId(4), input(std::nan(""))), std::invalid_argument);
  CHECK_THROWS_AS(
      link.send_setpoint(pa::VehicleId(4),
                         input(5.0, Eigen::Vector3d(0, std::numeric_limits<double>::infinity(), 0))),
      std::invalid_argument);
  CHECK(bus.pending() == 8);  // nothing sent for them
}

TEST_CASE(
    "TIMESYNC recovers the vehicle's clock offset through a delayed radio, across the vehicle clock's wrap") {
  // The vehicle's uint32 microsecond clock wraps 0.3 s into the run; the radio takes 8-10 ms
  // each way. Each way's delay is 8..11 ms (latency, jitter, the 1 ms steps), so the offset is
  // within half the difference of the two legs, 1.5 ms, of the truth.
  const double offset_s = kT0 - (kVehicleWrap_s - 0.3);
  Rig rig({1, 2}, {0.008, 0.002, 0.0, 3}, {offset_s, kT0 - 12.5});
  CHECK_FALSE(rig.link.status(pa::VehicleId(1)).clock_synced);
  CHECK(std::isnan(rig.link.ground_time(pa::VehicleId(1), 0)));
  rig.run(1.0);

  // 10 Hz to each vehicle, from when its session is known (its LINK_SESSION comes 6 ms after
  // its boot and 8-10 ms after its heartbeat has started the requests).
  CHECK(rig.sent_of_type(Type::timesync_request).size() == 18);
  CHECK(rig.link.counters().unsigned_dropped == 2 + 2);  // and the first two heartbeats
  for (std::uint8_t node : kBothNodes) {
    const auto& s = rig.link.status(pa::VehicleId(node));
    const double truth = node == 1 ? offset_s : kT0 - 12.5;
    REQUIRE(s.clock_synced);
    CHECK(std::abs(s.clock_offset_s - truth) <= 1.6e-3);
    CHECK(s.round_trip_s >= 0.016);
    CHECK(s.round_trip_s <= 0.0235);
    CHECK(s.clock_uncertainty_s >= 0.008);
    CHECK(std::abs(s.clock_offset_s - truth) <= s.clock_uncertainty_s);
  }
  // Vehicle stamps from before and after the wrap map to the ground times they were taken at.
  SimVehicle& v = rig.vehicle(0);
  for (double ago_s : {0.0, 0.2, 0.69, 0.71, 0.9}) {
    const double ground_s = rig.t() - ago_s;
    CHECK(std::abs(rig.link.ground_time(pa::VehicleId(1), v.clock_us(ground_s)) - ground_s) <= 1.6e-3);
  }
  CHECK(v.clock_us(rig.t() - 0.9) > v.clock_us(rig.t()));  // the stamps did wrap
  CHECK(rig.link.counters().stale == 0);
}

TEST_CASE("a vehicle that reboots restarts the clock sync on its new clock") {
  Rig rig({1}, {0.004, 0.0, 0.0, 5});
  rig.run(0.5);
  REQUIRE(rig.link.status(pa::VehicleId(1)).clock_synced);
  CHECK(rig.link.status(pa::VehicleId(1)).clock_resets == 0);
  rig.vehicle().powered = false;
  rig.run(0.3);
  CHECK(rig.link.status(pa::VehicleId(1)).lost);
  CHECK(rig.link.status(pa::VehicleId(1)).clock_synced);  // a silent vehicle keeps its clock
  rig.vehicle().reboot(rig.t());
  rig.vehicle().powered = true;
  rig.run_until([&] { return !rig.link.status(pa::VehicleId(1)).lost; }, 0.1);
  CHECK(rig.link.status(pa::VehicleId(1)).clock_resets == 1);
  rig.run(0.3);
  const auto& s = rig.link.status(pa::VehicleId(1));
  REQUIRE(s.clock_synced);
  CHECK(std::abs(s.clock_offset_s - rig.vehicle().clock_offset_s) <= 1.1e-3);
  CHECK(std::abs(rig.link.ground_time(pa::VehicleId(1), rig.vehicle().clock_us(rig.t())) - rig.t()) <=
        1.1e-3);
}

TEST_CASE(
    "a vehicle is lost after vehicle_timeout_s (0.3 s) without a heartbeat and found again with the next one") {
  Rig rig({1});
  rig.run(0.5);
  REQUIRE_FALSE(rig.link.status(pa::VehicleId(1)).lost);
  bool silent = false;
  rig.vehicle().drop_downlink = [&](const Message&) { return silent; };
  silent = true;
  const double last_s = rig.link.status(pa::VehicleId(1)).last_heard_s;
  const double timeout_s = gs::link::GroundLinkConfig{}.vehicle_timeout_s;
  rig.run_until([&] { return rig.t() > last_s + timeout_s - 0.005; }, 1.0);
  CHECK_FALSE(rig.link.status(pa::VehicleId(1)).lost);
  REQUIRE(rig.run_until([&] { return rig.link.status(pa::VehicleId(1)).lost; }, 1.0));
  const double lost_at_s = rig.t() - 1e-3;  // the tick of the step just run
  CHECK(lost_at_s - last_s > timeout_s);
  CHECK(lost_at_s - last_s <= timeout_s + 0.0015);
  CHECK(rig.link.status(pa::VehicleId(1)).last_heard_s == last_s);
  rig.run(1.0);
  CHECK(rig.link.status(pa::VehicleId(1)).lost);
  CHECK(rig.link.status(pa::VehicleId(1)).link_quality == 0.0);

  silent = false;
  CHECK(rig.run_until([&] { return !rig.link.status(pa::VehicleId(1)).lost; }, 0.021));
  CHECK(rig.link.status(pa::VehicleId(1)).last_heard_s > last_s);
  CHECK(rig.link.status(pa::VehicleId(1)).clock_resets == 0);  // silence is not a reboot: the clock ran on
}

TEST_CASE("link quality counts the vehicle's heartbeats against the 50 Hz expected") {
  Rig rig({1});
  SECTION("all arrive") {
    rig.run(2.0);
    CHECK(rig.link.status(pa::VehicleId(1)).link_quality >= 0.97);
  }
  SECTION("every second one is lost") {
    int n = 0;
    rig.vehicle().drop_downlink = [&](const Message& m) {
      return m.type == Type::vehicle_heartbeat && (n++ % 2) == 1;
    };
    rig.run(2.0);
    CHECK(rig.link.status(pa::VehicleId(1)).link_quality == Approx(0.5).margin(0.03));
    CHECK_FALSE(rig.link.status(pa::VehicleId(1)).lost);
  }
}

TEST_CASE("an IMPACT is reported on the ground clock, both its reports sharing the vehicle's count") {
  // the vehicle clock wraps between onset and reports
  const double offset_s = kT0 - (kVehicleWrap_s - 0.605);
  Rig rig({1}, {0.008, 0.002, 0.0, 11}, {offset_s});
  rig.run(0.6);
  REQUIRE(rig.link.status(pa::VehicleId(1)).clock_synced);
  CHECK(rig.link.take_impacts().empty());

  // A 40 m/s^2 push down the body z-axis for 3 ms: an unexpected impact for the firmware's detector.
  const double onset_s = rig.t();
  const float pulse[] = {20.0f, 40.0f, 40.0f, 20.0f};
  for (float p : pulse) {
    rig.vehicle().accel_z_mps2 = kG - p;
    rig.step();
  }
  rig.vehicle().accel_z_mps2 = kG;
  rig.run(0.2);
  REQUIRE(rig.vehicle().firmware->impact_count() == 1);

  const auto impacts = rig.link.take_impacts();
  REQUIRE(impacts.size() == 2);
  CHECK_FALSE(impacts[0].final);
  CHECK(impacts[1].final);
  for (const auto& r : impacts) {
    CHECK(r.vehicle == pa::kVehicle1);
    CHECK(r.count == rig.vehicle().firmware->impact_count());
    CHECK(r.t_from_clock_sync);
    // The onset, on the ground clock: within the 1.5 ms of the clock sync and the detector's
    // interpolation of a 1 kHz edge, of when the push began; not when the frame arrived.
    CHECK(std::abs(r.t_s - onset_s) <= 2.6e-3);
    CHECK(r.received_s - r.t_s >= 0.008);
    CHECK(r.peak_mps2 > 30.0f);
  }
  CHECK(impacts[0].t_s == Approx(impacts[1].t_s).margin(1e-3));  // the sync may improve in between
  CHECK(rig.link.take_impacts().empty());
}

TEST_CASE("IMPACT reports are kept in a bounded queue: the oldest go, counted") {
  InMemoryFrameBus bus;
  GroundLink link(bus, ids_of({1}), keyed({}, {1}));
  for (int i = 0; i < 100; ++i)
    link.on_frame(encoded(Impact{static_cast<std::uint32_t>(i) * 1000u, 12.0f, ImpactClass::catch_impact,
                                 false, static_cast<std::uint8_t>(i)},
                          1),
                  1.0 + 0.001 * i);
  const auto impacts = link.take_impacts();
  REQUIRE(impacts.size() == GroundLink::kImpactQueue);
  CHECK(link.counters().impacts_dropped == 100 - GroundLink::kImpactQueue);
  CHECK(impacts.front().count == 100 - GroundLink::kImpactQueue);
  CHECK(impacts.back().count == 99);
  // Without a clock sync (the vehicle never heard) the time is when the frame arrived.
  CHECK_FALSE(impacts.back().t_from_clock_sync);
  CHECK(impacts.back().t_s == Approx(1.099));
  CHECK(link.take_impacts().empty());
}

TEST_CASE("KILL: never gated, repeated until the vehicle reports killed, to one vehicle or all") {
  Rig rig({1, 2});
  rig.run(0.1);
  for (std::uint8_t node : kBothNodes) {
    rig.link.send_setpoint(pa::VehicleId(node), input(0.0));
    REQUIRE(rig.wait_for(rig.link.send_command(pa::VehicleId(node), CommandCode::arm, 0, rig.t())) ==
            CommandState::accepted);
  }
  // The first KILL to vehicle 1 is lost on its radio.
  int lost = 0;
  rig.vehicle(0).drop_uplink = [&](const Message& m) { return m.type == Type::kill && lost++ == 0; };
  rig.link.send_kill(pa::VehicleId(1), KillReason::operator_request);
  rig.run(0.5);
  CHECK(rig.vehicle(0).firmware->mode() == Mode::killed);
  CHECK(rig.vehicle(1).firmware->mode() == Mode::armed);
  CHECK(rig.link.status(pa::VehicleId(1)).mode == Mode::killed);
  CHECK(rig.sent_of_type(Type::kill).size() == 2);  // the lost one and one repeat: then confirmed

  rig.link.send_kill_all(KillReason::estimator);
  rig.run(0.3);
  CHECK(rig.vehicle(1).firmware->mode() == Mode::killed);
  CHECK(rig.sent_of_type(Type::kill).size() == 4);  // one to each, both confirmed after it
  CHECK(decoded(rig.sent_of_type(Type::kill).back().frame).node == 2);

  // DISARM clears the latch (and stops any repeat).
  REQUIRE(rig.wait_for(rig.link.send_command(pa::VehicleId(1), CommandCode::disarm, 0, rig.t())) ==
          CommandState::accepted);
  rig.run(0.1);
  CHECK(rig.vehicle(0).firmware->mode() == Mode::disarmed);
  CHECK(rig.link.status(pa::VehicleId(1)).mode == Mode::disarmed);
}

TEST_CASE("a KILL nobody confirms is sent command_attempts times, then given up") {
  Rig rig({1});
  rig.vehicle().drop_uplink = [](const Message& m) { return m.type == Type::kill; };
  rig.run(0.1);
  rig.link.send_kill(pa::VehicleId(1), KillReason::geofence);
  rig.run(1.0);
  CHECK(rig.sent_of_type(Type::kill).size() == 5);
  CHECK(rig.vehicle().firmware->mode() == Mode::disarmed);
}

TEST_CASE("malformed, unknown, foreign and wrong-direction frames are counted and dropped") {
  InMemoryFrameBus bus;
  GroundLink link(bus, ids_of({1, 2}), keyed({}, {1, 2}));
  const VehicleHeartbeat hb{1234, Mode::flying, kFlagArmed, 3, FailsafeReason::none, 0};

  Frame wrong_length = encoded(hb, 1);
  wrong_length.len = 7;
  link.on_frame(wrong_length, 1.0);
  CHECK(link.counters().wrong_length == 1);

  Frame unknown = encoded(hb, 1);
  unknown.id = make_id(static_cast<Type>(0x7F), 1);
  link.on_frame(unknown, 1.0);
  unknown.id = 0x900;  // beyond 11 bits
  link.on_frame(unknown, 1.0);
  CHECK(link.counters().unknown_type == 2);

  Frame bad_mode = encoded(hb, 1);
  bad_mode.data[4] = 9;
  link.on_frame(bad_mode, 1.0);
  Frame reserved_bit = encoded(hb, 1);
  reserved_bit.data[5] = 0x80;
  link.on_frame(reserved_bit, 1.0);
  CHECK(link.counters().out_of_range == 2);
  CHECK(link.counters().undecodable() == 5);

  const std::uint8_t not_ours[] = {kGroundNode, 3, 14, kBroadcastNode};
  for (std::uint8_t node : not_ours) link.on_frame(encoded(hb, node), 1.0);
  CHECK(link.counters().foreign_node == 4);

  // Ground-to-vehicle and HIL frames: another ground station, or a plant on the wrong bus.
  link.on_frame(encoded(GsHeartbeat{1, 0x77, GroundState::active, 1}, kBroadcastNode), 1.0);
  link.on_frame(encoded(RateThrust{{0, 0, 0}, 5.0f, 1}, 1), 1.0);
  link.on_frame(encoded(Command{CommandCode::arm, 0, 0x77, 0}, 1), 1.0);
  link.on_frame(encoded(HilImuGyro{{0, 0, 0}, 1}, 1), 1.0);
  CHECK(link.counters().wrong_direction == 4);

  // None of it touched what the link knows of vehicle 1.
  CHECK_FALSE(link.status(pa::VehicleId(1)).heard);
  CHECK(link.status(pa::VehicleId(1)).frames_received == 0);
  CHECK(link.status(pa::VehicleId(1)).mode == Mode::disarmed);

  // Valid frames that match nothing outstanding are stale.
  link.on_frame(
      encoded(CommandAck{0, CommandCode::arm, AckResult::accepted, Mode::armed, RefuseReason::none}, 1), 1.0);
  link.on_frame(encoded(TimesyncReply{5, 6}, 1), 1.0);
  link.on_frame(encoded(hb, 1), 1.0);
  link.on_frame(encoded(hb, 1), 1.001);  // the same heartbeat again
  CHECK(link.counters().stale == 3);
  CHECK(link.status(pa::VehicleId(1)).heartbeats_received == 1);
  CHECK(link.status(pa::VehicleId(1)).mode == Mode::flying);
  CHECK(link.status(pa::VehicleId(1)).frames_received == 4);

  const auto& c = link.counters();
  CHECK(c.frames_received == 17);
  CHECK(c.accepted + c.undecodable() + c.foreign_node + c.wrong_direction + c.stale == c.frames_received);
  CHECK(c.frames_sent == 0);
}

TEST_CASE("on_frame returns the message it used, and nothing for a frame it dropped") {
  InMemoryFrameBus bus;
  GroundLink link(bus, ids_of({1, 2}), keyed({}, {1, 2}));
  const TelemetryRates rates{{0.5f, -0.25f, 0.0f}, 9.81f, 0x2};
  const std::optional<Message> used = link.on_frame(encoded(rates, 2), 1.0);
  REQUIRE(used);
  CHECK(used->type == Type::telemetry_rates);
  CHECK(used->node == 2);
  CHECK(used->telemetry_rates.rate_radps[0] == 0.5f);
  CHECK(used->telemetry_rates.saturation == 0x2);
  CHECK_FALSE(link.on_frame(encoded(rates, 3), 1.0));                           // foreign
  CHECK_FALSE(link.on_frame(encoded(RateThrust{{0, 0, 0}, 5.0f, 1}, 1), 1.0));  // wrong direction
  Frame short_frame = encoded(rates, 1);
  short_frame.len = 3;
  CHECK_FALSE(link.on_frame(short_frame, 1.0));                      // undecodable
  CHECK_FALSE(link.on_frame(encoded(TimesyncReply{5, 6}, 1), 1.0));  // stale
  CHECK(link.counters().accepted == 1);
}

TEST_CASE("the bus refusing a frame is counted") {
  InMemoryFrameBus bus(2);
  GroundLink link(bus, ids_of({1}), keyed({}, {1}));
  link.on_frame(encoded(LinkSession{7, 0}, 1), 0.0);
  link.tick(0.0);  // the first heartbeat and its AUTH fill it
  CHECK(link.counters().frames_sent == 2);
  link.send_setpoint(pa::VehicleId(1), input(0.0));
  CHECK(link.counters().send_refused == 1);
  CHECK(bus.take().size() == 2);
  link.send_setpoint(pa::VehicleId(1), input(0.0));
  CHECK(link.counters().frames_sent == 4);
  CHECK(link.counters().send_refused == 1);
}

TEST_CASE("frames go out only in a session the vehicle announced, each followed by its AUTH") {
  InMemoryFrameBus bus;
  GroundLink link(bus, ids_of({1}), keyed({}, {1}));
  link.send_setpoint(pa::VehicleId(1), input(0.0));
  CHECK(bus.take().empty());
  CHECK(link.counters().unsigned_dropped == 1);

  link.on_frame(encoded(LinkSession{0xABCD, 41}, 1), 0.0);
  link.send_setpoint(pa::VehicleId(1), input(2.0));
  const std::vector<Frame> frames = bus.take();
  REQUIRE(frames.size() == 2);
  const Message auth = decoded(frames[1]);
  REQUIRE(auth.type == Type::auth);
  CHECK(auth.node == 1);
  CHECK(auth.auth.counter_low == 42);  // above the vehicle's last accepted counter
  // The vehicle with this key and nonce accepts it.
  fw::LinkConfig vehicle;
  vehicle.key = test_key(1);
  vehicle.session_nonce = 0xABCD;
  fw::LinkGuard guard(vehicle);
  guard.on_frame(frames[0], decoded(frames[0]), 0);
  guard.on_auth(frames[1]);
  Message out;
  bool verified = false;
  std::uint32_t received_us = 0;
  for (int step = 0; step < pa::auth::TagCheck::kSteps; ++step)
    verified = guard.verify_next(out, received_us);
  CHECK(verified);
  CHECK(out.type == Type::rate_thrust);
  CHECK(guard.last_counter() == 42);

  // A ground station restarted while the vehicle flies: the vehicle's counter is far ahead.
  link.on_frame(encoded(LinkSession{0xABCD, 5000}, 1), 0.1);
  link.send_setpoint(pa::VehicleId(1), input(2.0));
  CHECK(decoded(bus.take()[1]).auth.counter_low == 5001);
  // A vehicle reboot: a new nonce, counting from the start.
  link.on_frame(encoded(LinkSession{0x1234, 0}, 1), 0.2);
  link.send_setpoint(pa::VehicleId(1), input(2.0));
  CHECK(decoded(bus.take()[1]).auth.counter_low == 1);
  CHECK(link.counters().sessions_started == 3);
}

TEST_CASE("a flood of 100k random frames neither crashes the link nor makes it allocate") {
  InMemoryFrameBus bus;
  GroundLink link(bus, ids_of({1, 2}), keyed({}, {1, 2}));
  std::mt19937 rng(20240611);
  std::uniform_int_distribution<int> byte(0, 255);
  std::uniform_int_distribution<int> node(0, 15);
  std::uniform_int_distribution<int> length(0, 9);
  std::uniform_int_distribution<int> any_id(0, 0xFFFF);
  std::uniform_int_distribution<std::size_t> catalogue(0, kCatalogue.size() - 1);

  std::uint64_t allocations = 0;
  double t = 10.0;
  for (int i = 0; i < 100000; ++i) {
    Frame f;
    if (i % 2 == 0) {  // a known type and its length, random payload: many of these decode
      const TypeInfo& info = kCatalogue[catalogue(rng)];
      f.id = make_id(info.type, static_cast<std::uint8_t>(node(rng)));
      f.len = info.length;
    } else {  // anything at all
      f.id = static_cast<std::uint16_t>(any_id(rng));
      f.len = static_cast<std::uint8_t>(length(rng));
    }
    for (auto& b : f.data) b = static_cast<std::uint8_t>(byte(rng));
    const std::uint64_t before = g_allocations;
    link.on_frame(f, t);
    allocations += g_allocations - before;
    if (i % 100 == 0) {
      t += 0.001;
      link.tick(t);
      bus.take();
    }
  }
  CHECK(allocations == 0);
  const auto& c = link.counters();
  CHECK(c.frames_received == 100000);
  CHECK(c.accepted + c.undecodable() + c.foreign_node + c.wrong_direction + c.stale == c.frames_received);
  CHECK(c.accepted > 0);
  CHECK(c.undecodable() > 0);
  CHECK(link.take_impacts().size() <= GroundLink::kImpactQueue);
  for (std::uint8_t n : kBothNodes) {
    CHECK(link.status(pa::VehicleId(n)).link_quality >= 0.0);
    CHECK(link.status(pa::VehicleId(n)).link_quality <= 1.0);
  }
  // Still working: the periodic frames go out.
  link.tick(t + 1.0);
  CHECK_FALSE(bus.take().empty());
}
