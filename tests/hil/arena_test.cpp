// The arena in lockstep (hil/sil/arena.hpp): the plant, both vehicles flown by the real
// firmware core, a radio per vehicle and the motion capture, seen only from the ground bus and
// the motion-capture frames. A small ground stand-in sends what a ground station sends (50 Hz
// GS_HEARTBEAT, 200 Hz zero-thrust RATE_THRUST, ARM) and the assertions are on what comes back
// and on the firmware's mode; the radio's timing is checked against the header's contract.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>
#include <vector>

#include "hil/plant/plant_config.hpp"
#include "hil/sil/arena.hpp"

using namespace pa::proto;
using hil::sil::Arena;

namespace {

constexpr std::uint16_t kSession = 0x5A17;
constexpr double kLatency_s = 0.008;
constexpr double kEps_s = 1e-9;

hil::sil::ArenaConfig exact_radio(double loss = 0.0) {
  hil::sil::ArenaConfig c{};
  c.radio.latency_s = kLatency_s;
  c.radio.jitter_s = 0.0;
  c.radio.loss = loss;
  return c;
}

// One frame as the ground bus saw it.
struct Arrival {
  long step;
  double t_s;
  Frame frame;
  Message m;
};

// The ground station's side, just enough to arm: heartbeats and a zero-thrust setpoint stream
// to `to` (a node, broadcast, or kEachVehicle), commands, and every frame that came back with its
// arrival time. Frames to a vehicle go with their AUTH once its LINK_SESSION has been heard (as
// the ground station does; docs/security.md); broadcasts carry none.
constexpr std::uint8_t kEachVehicle = 0xFF;  // a signed copy to each vehicle

class Ground {
 public:
  Ground(Arena& arena, std::uint8_t to) : arena_(arena), to_(to) {}

  // The node frames are encoded for (send() readdresses the copies for kEachVehicle).
  std::uint8_t address() const { return to_ == kEachVehicle ? kBroadcastNode : to_; }

  void send(const Frame& f) {
    if (to_ == kBroadcastNode) {
      arena_.send_from_ground(f);
      return;
    }
    for (const pa::VehicleId v : pa::kActVehicles) {
      if (to_ != kEachVehicle && to_ != v.node()) continue;
      Frame g = f;
      g.id = make_id(static_cast<Type>(id_type(f.id)), v.node());
      Frame auth;
      if (!signers_[pa::act_slot(v)].sign(g, auth)) continue;  // no session yet
      arena_.send_from_ground(g);
      arena_.send_from_ground(auth);
    }
  }

  float thrust_mps2 = 0.0f;
  std::array<float, 3> rate_radps{};

  // One arena step, with the periodic frames due now sent first.
  void tick() {
    Frame f;
    if (steps_ % 20 == 0 &&
        encode(GsHeartbeat{static_cast<std::uint32_t>(steps_), kSession, GroundState::active, hb_seq_++},
               address(), f))
      send(f);
    if (steps_ % 5 == 0 &&
        encode(RateThrust{rate_radps, thrust_mps2, static_cast<std::uint8_t>(sp_seq_++ & 0x0Fu)}, address(),
               f))
      send(f);
    ++steps_;
    arena_.step();
    for (const Frame& g : arena_.take_ground_frames()) {
      Arrival a{steps_, arena_.t_s(), g, {}};
      REQUIRE(decode(g, a.m) == DecodeStatus::ok);
      if (a.m.type == Type::link_session) {
        pa::auth::Signer& signer = signers_[pa::act_slot(pa::VehicleId(a.m.node))];
        if (!signer.active()) signer.start_session(a.m.link_session.nonce, a.m.link_session.last_counter);
      }
      arrivals_.push_back(a);
    }
  }
  void run(double seconds) {
    const long n = std::lround(seconds / arena_.period_s());
    for (long k = 0; k < n; ++k) tick();
  }
  // Sends ARM to `to_` now; returns its sequence number.
  std::uint8_t send_arm() {
    Frame f;
    const std::uint8_t seq = cmd_seq_++;
    REQUIRE(encode(Command{CommandCode::arm, seq, kSession, 0}, address(), f));
    send(f);
    return seq;
  }

  const std::vector<Arrival>& arrivals() const { return arrivals_; }
  // The COMMAND_ACK for `seq` from `node`, if it arrived.
  std::optional<Arrival> ack(std::uint8_t node, std::uint8_t seq) const {
    for (const Arrival& a : arrivals_)
      if (a.m.type == Type::command_ack && a.m.node == node && a.m.command_ack.seq == seq) return a;
    return std::nullopt;
  }
  int count(Type type, std::uint8_t node) const {
    return static_cast<int>(std::count_if(arrivals_.begin(), arrivals_.end(), [&](const Arrival& a) {
      return a.m.type == type && a.m.node == node;
    }));
  }

 private:
  Arena& arena_;
  std::uint8_t to_;
  long steps_ = 0;
  std::uint8_t hb_seq_ = 0;
  unsigned sp_seq_ = 0;
  std::uint8_t cmd_seq_ = 0;
  std::vector<Arrival> arrivals_;
  std::array<pa::auth::Signer, 2> signers_{pa::auth::Signer(hil::sil::simulation_key(pa::kVehicle1)),
                                           pa::auth::Signer(hil::sil::simulation_key(pa::kVehicle2))};
};

bool same_frame(const Frame& a, const Frame& b) {
  return a.id == b.id && a.len == b.len && std::memcmp(a.data.data(), b.data.data(), a.len) == 0;
}

}  // namespace

TEST_CASE("arena: vehicle 1 and vehicle 2, the firmware of each flying its own plant vehicle") {
  Arena arena(hil::PlantConfig{}, exact_radio(), 1);
  CHECK(arena.vehicle(pa::kVehicle1).vehicle() == pa::kVehicle1);
  CHECK(arena.vehicle(pa::kVehicle2).vehicle() == pa::kVehicle2);
  CHECK_THROWS_AS(arena.vehicle(pa::VehicleId(0)), std::out_of_range);
  CHECK_THROWS_AS(arena.vehicle(pa::VehicleId(3)), std::out_of_range);
  CHECK(arena.period_s() == Approx(0.001));

  hil::PlantConfig slow{};
  slow.imu.rate_Hz = 500;
  CHECK_THROWS_AS(Arena(slow, exact_radio(), 1), std::invalid_argument);
  hil::sil::ArenaConfig bad = exact_radio();
  bad.radio.loss = 1.5;
  CHECK_THROWS_AS(Arena(hil::PlantConfig{}, bad, 1), std::invalid_argument);
}

TEST_CASE("arena: frames addressed to node 2 reach vehicle 2 only, after the radio latency, and it answers") {
  Arena arena(hil::PlantConfig{}, exact_radio(), 3);
  Ground ground(arena, 2);
  ground.run(0.2);
  CHECK(arena.vehicle(pa::kVehicle1).firmware().mode() == Mode::disarmed);
  CHECK(arena.vehicle(pa::kVehicle2).firmware().mode() == Mode::disarmed);

  // ARM at t_c: read by the firmware at t_c + L, checked over its next three ticks and executed
  // in the third (t_c + L + 3 ms).
  const double t_c = arena.t_s();
  const std::uint8_t seq = ground.send_arm();
  const long to_read = std::lround(kLatency_s / arena.period_s()) + pa::auth::TagCheck::kSteps - 1;
  for (long k = 0; k < to_read; ++k) ground.tick();
  CHECK(arena.vehicle(pa::kVehicle2).firmware().mode() == Mode::disarmed);
  ground.tick();
  CHECK(arena.vehicle(pa::kVehicle2).firmware().mode() == Mode::armed);
  ground.run(0.05);
  CHECK(arena.vehicle(pa::kVehicle2).firmware().mode() == Mode::armed);
  CHECK(arena.vehicle(pa::kVehicle1).firmware().mode() == Mode::disarmed);

  // The ACK crosses the radio back: on the ground bus at t_c + 2 L + 3 ms, no earlier.
  const std::optional<Arrival> ack = ground.ack(2, seq);
  REQUIRE(ack);
  CHECK(ack->m.command_ack.result == AckResult::accepted);
  CHECK(ack->t_s >= t_c + 2 * kLatency_s);
  CHECK(ack->t_s == Approx(t_c + 2 * kLatency_s + 0.003).margin(kEps_s));
  CHECK_FALSE(ground.ack(1, seq));

  // Both vehicles' heartbeats come back (each vehicle talks to the ground whatever it heard),
  // each exactly one radio latency after the vehicle time it was sent at.
  CHECK(ground.count(Type::vehicle_heartbeat, 1) > 0);
  CHECK(ground.count(Type::vehicle_heartbeat, 2) > 0);
  for (const Arrival& a : ground.arrivals()) {
    if (a.m.type != Type::vehicle_heartbeat) continue;
    const double sent_s = a.m.vehicle_heartbeat.uptime_ms * 1e-3;
    CHECK(a.t_s >= sent_s + kLatency_s - kEps_s);
    CHECK(a.t_s == Approx(sent_s + kLatency_s).margin(kEps_s));
  }

  // Nothing went over node 1's radio; every frame sent to node 2 was delivered once the radio
  // had time to carry the last ones.
  for (int k = 0; k < 10; ++k) arena.step();
  const hil::run::VehicleExchangeCounters r1 = arena.exchange().counters(pa::kVehicle1),
                                          r2 = arena.exchange().counters(pa::kVehicle2);
  CHECK(r1.uplink_offered == 0);
  CHECK(r1.uplink_delivered == 0);
  CHECK(r2.uplink_offered > 0);
  CHECK(r2.uplink_delivered == r2.uplink_offered);
  CHECK(r2.uplink_lost == 0);
  CHECK(r1.downlink_delivered > 0);
  CHECK(r2.downlink_delivered > 0);
  // In process every sample is answered before the next step.
  for (const hil::run::VehicleExchangeCounters& r : {r1, r2}) {
    CHECK(r.samples_sent == r.answered);
    CHECK(r.missed == 0);
  }
}

TEST_CASE("arena: broadcast frames reach both vehicles, which do not act on them (they carry no AUTH)") {
  Arena arena(hil::PlantConfig{}, exact_radio(), 4);
  Ground ground(arena, kBroadcastNode);
  ground.run(0.2);
  const std::uint8_t seq = ground.send_arm();
  ground.run(0.05);
  for (const pa::VehicleId vehicle : pa::kActVehicles) {
    CHECK(arena.vehicle(vehicle).firmware().mode() == Mode::disarmed);
    CHECK_FALSE(ground.ack(vehicle.node(), seq));
    CHECK(arena.vehicle(vehicle).firmware().guard().forged() > 0);  // counted
  }
  for (int k = 0; k < 10; ++k) arena.step();  // the last frames still in flight land
  const hil::run::VehicleExchangeCounters r1 = arena.exchange().counters(pa::kVehicle1),
                                          r2 = arena.exchange().counters(pa::kVehicle2);
  CHECK(r1.uplink_offered > 0);
  CHECK(r1.uplink_offered == r2.uplink_offered);
  CHECK(r1.uplink_delivered == r1.uplink_offered);
  CHECK(r2.uplink_delivered == r2.uplink_offered);
}

TEST_CASE("arena: with jitter, frames still arrive in order within latency + jitter + one step") {
  hil::sil::ArenaConfig config = exact_radio();
  config.radio.jitter_s = 0.004;
  Arena arena(hil::PlantConfig{}, config, 5);
  Ground ground(arena, kBroadcastNode);
  ground.run(0.5);
  std::array<double, 2> last_sent{-1.0, -1.0};
  int heartbeats = 0;
  for (const Arrival& a : ground.arrivals()) {
    if (a.m.type != Type::vehicle_heartbeat) continue;
    ++heartbeats;
    const double sent_s = a.m.vehicle_heartbeat.uptime_ms * 1e-3;
    CHECK(a.t_s >= sent_s + kLatency_s - kEps_s);
    CHECK(a.t_s <= sent_s + kLatency_s + config.radio.jitter_s + 0.001 + kEps_s);
    double& last = last_sent[pa::act_slot(pa::VehicleId(a.m.node))];
    CHECK(sent_s > last);
    last = sent_s;
  }
  CHECK(heartbeats >= 2 * 24);
}

TEST_CASE("arena: with loss 1 nothing arrives either way (plant_exchange_test counts it)") {
  Arena arena(hil::PlantConfig{}, exact_radio(1.0), 6);
  Ground ground(arena, kBroadcastNode);
  ground.run(0.2);
  ground.send_arm();
  ground.run(0.1);
  CHECK(ground.arrivals().empty());
  CHECK(arena.vehicle(pa::kVehicle1).firmware().mode() == Mode::disarmed);
  CHECK(arena.vehicle(pa::kVehicle2).firmware().mode() == Mode::disarmed);
}

TEST_CASE("arena: motion capture at its rate and latency, with both vehicles and the pole") {
  hil::PlantConfig plant{};
  plant.mocap.latency_s = 0.013;
  plant.mocap.jitter_s = 0.0;
  plant.mocap.dropout_probability = 0.0;
  Arena arena(plant, exact_radio(), 8);
  std::vector<std::pair<double, hil::CapturedFrame>> got;
  for (int k = 0; k < 1000; ++k) {
    arena.step();
    for (const hil::CapturedFrame& m : arena.take_mocap()) got.emplace_back(arena.t_s(), m);
  }
  // Captured every 5 ms from t = 0; delivered 13 ms later: the last one by 1 s was captured at 985 ms.
  REQUIRE(got.size() == 198);
  const hil::Plant& p = arena.plant();
  for (std::size_t i = 0; i < got.size(); ++i) {
    const auto& [arrived_s, m] = got[i];
    CHECK(m.index == i);
    CHECK(m.capture_t_s == Approx(0.005 * static_cast<double>(i)).margin(kEps_s));
    CHECK(m.delivery_t_s == Approx(m.capture_t_s + 0.013).margin(kEps_s));
    CHECK(arrived_s >= m.delivery_t_s - kEps_s);
    CHECK(arrived_s < m.delivery_t_s + 0.001 - kEps_s);
    // The vehicles stay parked and the pole on the floor: the poses are the truth within noise.
    for (int b = 0; b < 3; ++b) REQUIRE(m.pose[static_cast<std::size_t>(b)].seen);
    CHECK((m.pose[0].position_m - p.vehicle(pa::kVehicle1).body.position_m).norm() < 0.01);
    CHECK((m.pose[1].position_m - p.vehicle(pa::kVehicle2).body.position_m).norm() < 0.01);
    CHECK((m.pose[2].position_m - p.pole().body.position_m).norm() < 0.01);
  }
  // Which body is which: vehicle1 at x = -1, vehicle2 at +1, the pole between them.
  CHECK(got.back().second.pose[0].position_m.x() == Approx(-1.0).margin(0.01));
  CHECK(got.back().second.pose[1].position_m.x() == Approx(1.0).margin(0.01));
  CHECK(got.back().second.pose[2].position_m.x() == Approx(0.0).margin(0.01));
  CHECK(arena.take_mocap().empty());
}

namespace {

// Everything the ground sees of a run, and the plant's end state.
struct Run {
  std::vector<Arrival> ground;
  std::vector<hil::CapturedFrame> mocap;
  std::vector<std::uint64_t> lost1, lost2;  // per step, each radio's losses so far (both ways)
  std::array<hil::VehicleState, 2> vehicles;
  hil::PoleState pole;
  std::array<Mode, 2> modes;
};

// Heartbeats and setpoints to each vehicle through lossy, jittery radios, ARM every 100 ms (a
// lost one is retried; once armed, the repeats are refused), then 0.8 g with a small rate demand:
// the firmware's rate loop then flies on the seed's IMU noise.
Run fly(std::uint64_t seed) {
  hil::sil::ArenaConfig config{};
  config.radio.latency_s = 0.005;
  config.radio.jitter_s = 0.003;
  config.radio.loss = 0.2;
  Arena arena(hil::PlantConfig{}, config, seed);
  Ground ground(arena, kEachVehicle);
  Run run;
  for (long k = 0; k < 700; ++k) {
    if (k >= 200 && k % 100 == 0) ground.send_arm();
    if (k == 500) {
      ground.thrust_mps2 = static_cast<float>(0.8 * 9.81);
      ground.rate_radps = {0.1f, -0.1f, 0.0f};
    }
    ground.tick();
    for (const hil::CapturedFrame& m : arena.take_mocap()) run.mocap.push_back(m);
    const hil::run::VehicleExchangeCounters r1 = arena.exchange().counters(pa::kVehicle1),
                                            r2 = arena.exchange().counters(pa::kVehicle2);
    run.lost1.push_back(r1.uplink_lost + r1.downlink_lost);
    run.lost2.push_back(r2.uplink_lost + r2.downlink_lost);
  }
  run.ground = ground.arrivals();
  run.vehicles = {arena.plant().vehicle(pa::kVehicle1), arena.plant().vehicle(pa::kVehicle2)};
  run.pole = arena.plant().pole();
  run.modes = {arena.vehicle(pa::kVehicle1).firmware().mode(),
               arena.vehicle(pa::kVehicle2).firmware().mode()};
  return run;
}

// The frame without what the host's wall clock put in it: TELEMETRY_STATUS reports the
// firmware's longest tick and its overruns as measured on the machine running it.
Frame reproducible(const Arrival& a) {
  if (a.m.type != Type::telemetry_status) return a.frame;
  TelemetryStatus status = a.m.telemetry_status;
  status.tick_time_max_us = 0;
  status.overruns = 0;
  Frame f;
  REQUIRE(encode(status, a.m.node, f));
  return f;
}

bool same_ground(const Run& a, const Run& b) {
  if (a.ground.size() != b.ground.size()) return false;
  for (std::size_t i = 0; i < a.ground.size(); ++i)
    if (a.ground[i].step != b.ground[i].step ||
        !same_frame(reproducible(a.ground[i]), reproducible(b.ground[i])))
      return false;
  return true;
}

bool same_mocap(const Run& a, const Run& b) {
  if (a.mocap.size() != b.mocap.size()) return false;
  for (std::size_t i = 0; i < a.mocap.size(); ++i) {
    const hil::CapturedFrame &x = a.mocap[i], &y = b.mocap[i];
    if (x.index != y.index || x.delivery_t_s != y.delivery_t_s) return false;
    for (std::size_t p = 0; p < 3; ++p)
      if (x.pose[p].seen != y.pose[p].seen || x.pose[p].position_m != y.pose[p].position_m ||
          x.pose[p].attitude.coeffs() != y.pose[p].attitude.coeffs())
        return false;
  }
  return true;
}

bool same_vehicle(const hil::VehicleState& a, const hil::VehicleState& b) {
  return a.body.position_m == b.body.position_m && a.body.velocity_mps == b.body.velocity_mps &&
         a.body.attitude.coeffs() == b.body.attitude.coeffs() &&
         a.body.rate_body_radps == b.body.rate_body_radps && a.motor_thrust_N == b.motor_thrust_N;
}

}  // namespace

TEST_CASE("arena: one seed gives the same run bit for bit; another seed another run") {
  const Run a = fly(21), b = fly(21), c = fly(22);
  // The run did something: both vehicles armed through the lossy radios and flew the demand.
  CHECK(a.modes[0] == Mode::flying);
  CHECK(a.modes[1] == Mode::flying);
  CHECK(a.ground.size() > 200);
  CHECK(a.mocap.size() > 100);
  double thrust_N = 0.0;
  for (double f : a.vehicles[0].motor_thrust_N) thrust_N += f;
  CHECK(thrust_N > 2.0);

  const auto is_status = [](const Arrival& x) { return x.m.type == Type::telemetry_status; };
  CHECK(std::count_if(a.ground.begin(), a.ground.end(), is_status) > 0);
  CHECK(same_ground(a, b));
  CHECK(same_mocap(a, b));
  CHECK(a.lost1 == b.lost1);
  CHECK(a.lost2 == b.lost2);
  CHECK(same_vehicle(a.vehicles[0], b.vehicles[0]));
  CHECK(same_vehicle(a.vehicles[1], b.vehicles[1]));
  CHECK(a.pole.body.position_m == b.pole.body.position_m);

  CHECK_FALSE(same_ground(a, c));
  CHECK_FALSE(same_mocap(a, c));
  CHECK(a.lost1 != c.lost1);
  CHECK_FALSE(same_vehicle(a.vehicles[0], c.vehicles[0]));
  CHECK_FALSE(same_vehicle(a.vehicles[1], c.vehicles[1]));

  // The two radios draw apart although they carry the same broadcast traffic.
  CHECK(a.lost1 != a.lost2);
}
