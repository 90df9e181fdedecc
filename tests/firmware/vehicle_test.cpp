// The vehicle composition through its only interface, frames and IMU samples.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "fw/selftest.hpp"
#include "fw/vehicle.hpp"

using namespace pa::proto;

namespace {

constexpr std::uint8_t kNode = 1;
constexpr std::uint16_t kToken = 0x4242;
constexpr float kG = 9.81f;

constexpr pa::auth::Key kKey{1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16};
constexpr std::uint32_t kNonce = 77;

fw::VehicleConfig keyed_config() {
  fw::VehicleConfig c{};
  c.link.key = kKey;
  c.link.session_nonce = kNonce;
  return c;
}

struct Bench {
  fw::VehicleConfig config = keyed_config();
  pa::auth::Signer signer{kKey};
  fw::Vehicle vehicle;
  std::uint32_t now_us = 0;
  std::uint8_t sp_seq = 0, hb_seq = 0, cmd_seq = 0;
  std::vector<Message> sent;
  fw::Vec3f gyro_radps{};       // what the gyro reads at rest (a bias)
  fw::Vec3f accel_bias_mps2{};  // what the accelerometer reads more than the specific force

  Bench() : vehicle(config) { signer.start_session(kNonce, 0); }
  explicit Bench(const fw::VehicleConfig& c) : config(c), vehicle(config) { signer.start_session(kNonce, 0); }

  // As the ground sends it: the frame, then its AUTH. The vehicle checks it over its next ticks.
  template <class M>
  void queue(const M& m, std::uint8_t node = kNode) {
    Frame f;
    Frame auth;
    REQUIRE(encode(m, node, f));
    REQUIRE(signer.sign(f, auth));
    vehicle.on_frame(f, now_us);
    vehicle.on_frame(auth, now_us);
  }
  // ... and the ticks until it has been checked and acted on (a few ms with no ground streams;
  // a command waits for a tick that sends no telemetry).
  template <class M>
  void receive(const M& m, std::uint8_t node = kNode) {
    queue(m, node);
    while (vehicle.guard().queued() > 0 || vehicle.link().command_waiting()) tick(false);
  }
  void heartbeat(std::uint16_t token = kToken) {
    queue(GsHeartbeat{now_us / 1000, token, GroundState::active, hb_seq++});
  }
  void setpoint(float thrust, fw::Vec3f rates = {}) {
    sp_seq = static_cast<std::uint8_t>((sp_seq + 1) & 0x0F);
    queue(RateThrust{rates, thrust, sp_seq});
  }
  void command(CommandCode code, std::int32_t arg = 0, std::uint16_t token = kToken) {
    receive(Command{code, cmd_seq++, token, arg});
  }
  // One ms at rest (level, on the ground), with the ground's streams as asked. The heartbeat
  // and the setpoint never share a tick, so each frame is acted on in the next tick (the
  // vehicle verifies one ground frame per tick).
  fw::TickOutput tick(bool with_heartbeat = true, float thrust = -1, float accel_z = kG) {
    if (with_heartbeat && now_us % 20000 == 1000) heartbeat();
    if (thrust >= 0 && now_us % 5000 == 0) setpoint(thrust);
    fw::ImuSample s;
    s.t_us = now_us;
    s.accel_mps2 = {accel_bias_mps2[0], accel_bias_mps2[1], accel_z + accel_bias_mps2[2]};
    s.gyro_radps = gyro_radps;
    const fw::TickOutput out = vehicle.tick(s);
    Frame f;
    while (vehicle.pop_tx(f)) {
      Message m;
      REQUIRE(decode(f, m) == DecodeStatus::ok);
      sent.push_back(m);
    }
    now_us += 1000;
    return out;
  }
  const CommandAck* last_ack() const {
    for (auto it = sent.rbegin(); it != sent.rend(); ++it)
      if (it->type == Type::command_ack) return &it->command_ack;
    return nullptr;
  }
  void settle(int ms, float thrust = 0) {
    for (int i = 0; i < ms; ++i) tick(true, thrust);
  }
};

}  // namespace

TEST_CASE("arming over the link: accepted with the session, a live heartbeat and zero thrust") {
  Bench b;
  b.settle(50);
  b.command(CommandCode::arm);
  b.tick(true, 0);
  REQUIRE(b.last_ack() != nullptr);
  CHECK(b.last_ack()->result == AckResult::accepted);
  CHECK(b.vehicle.mode() == Mode::armed);
}

TEST_CASE("armed on the floor the rate integrators do not wind up: lift-off is the same after 20 ms or 3 s") {
  // A gyro bias the rate loop tries to cancel while the feet hold the vehicle still.
  const auto lift_off = [](int armed_ms) {
    Bench b;
    b.gyro_radps = {0.05f, -0.03f, 0.02f};
    b.settle(60);
    b.command(CommandCode::arm);
    b.settle(armed_ms);
    REQUIRE(b.vehicle.mode() == Mode::armed);
    std::vector<fw::Motors> commands;
    for (int i = 0; i < 40; ++i) commands.push_back(b.tick(true, kG).motor_command);
    CHECK(b.vehicle.mode() == Mode::flying);
    return commands;
  };
  const std::vector<fw::Motors> soon = lift_off(20), late = lift_off(3000);
  for (std::size_t i = 0; i < soon.size(); ++i)
    for (int m = 0; m < 4; ++m) CHECK(late[i][m] == Approx(soon[i][m]).margin(1e-6));
}

TEST_CASE("arming is refused with the reason the operator needs") {
  Bench b;
  SECTION("a command from another session") {
    b.settle(50);
    b.command(CommandCode::arm, 0, 0x9999);
    b.tick(true, 0);
    CHECK(b.last_ack()->reason == RefuseReason::bad_session_token);
  }
  SECTION("no live ground heartbeat") {
    b.settle(50);
    for (std::uint32_t i = 0; i < fw::SupervisorConfig{}.heartbeat_timeout_us / 1000u + 50u; ++i)
      b.tick(false, 0);
    b.command(CommandCode::arm);
    b.tick(false, 0);
    CHECK(b.last_ack()->reason == RefuseReason::no_ground_heartbeat);
  }
  SECTION("thrust not zero") {
    b.settle(50, 3.0f);
    b.command(CommandCode::arm);
    b.tick(true, 3.0f);
    CHECK(b.last_ack()->reason == RefuseReason::thrust_not_zero);
  }
  CHECK(b.last_ack()->result == AckResult::refused);
  CHECK(b.vehicle.mode() == Mode::disarmed);
}

TEST_CASE("flying, a KILL stops the motors at once and stays latched until disarmed") {
  Bench b;
  b.settle(50);
  b.command(CommandCode::arm);
  b.settle(20);
  b.settle(50, kG);
  REQUIRE(b.vehicle.mode() == Mode::flying);
  CHECK(b.tick(true, kG).motors_enabled);
  b.receive(Kill{0, KillReason::operator_request});  // any token
  CHECK_FALSE(b.tick(true, kG).motors_enabled);
  CHECK(b.vehicle.mode() == Mode::killed);
  b.settle(100, 0);
  CHECK(b.vehicle.mode() == Mode::killed);
  b.command(CommandCode::disarm);
  b.tick(true, 0);
  CHECK(b.vehicle.mode() == Mode::disarmed);
}

// Found by tests/fuzz/vehicle_fuzz.cpp: a KILL, DISARM and ARM read between two ticks used to
// leave the vehicle armed, because the KILL latch lost their order. Ground frames are now acted
// on one per tick in the order they came; a KILL goes first and supersedes what came before it.
TEST_CASE("ground frames are acted on one per tick in order; a KILL first, superseding earlier ones") {
  Bench b;
  b.settle(50);
  b.command(CommandCode::arm);
  b.settle(5);
  REQUIRE(b.vehicle.mode() == Mode::armed);
  b.queue(Command{CommandCode::disarm, b.cmd_seq++, kToken, 0});
  b.queue(Command{CommandCode::arm, b.cmd_seq++, kToken, 0});
  b.queue(Kill{0, KillReason::operator_request});
  // Its check takes three ticks: two without a change, then motors off in the third.
  CHECK(b.tick(false).motors_enabled);
  CHECK(b.tick(false).motors_enabled);
  CHECK_FALSE(b.tick(false).motors_enabled);
  CHECK(b.vehicle.mode() == Mode::killed);
  b.settle(10, 0);
  CHECK(b.vehicle.mode() == Mode::killed);  // the DISARM and ARM sent before it are moot
  // After the KILL, a DISARM clears it and the next ARM is the operator's new decision.
  b.command(CommandCode::disarm);
  b.tick(false);
  CHECK(b.vehicle.mode() == Mode::disarmed);
  b.command(CommandCode::arm);
  b.tick(false);
  CHECK(b.vehicle.mode() == Mode::armed);
}

namespace {
bool is_telemetry(Type t) {
  return t == Type::vehicle_heartbeat || t == Type::link_session || t == Type::telemetry_rates ||
         t == Type::telemetry_attitude || t == Type::telemetry_motors || t == Type::telemetry_status;
}
}  // namespace

// The ARM's and the LAND's ticks were the firmware's heaviest (over the budget of 1,500
// instructions in the processor-in-the-loop flight): a command's work on top of a telemetry frame.
TEST_CASE("a command waits for a tick that sends no telemetry, at most 7 ms") {
  int waited = 0, longest = 0;
  for (int offset = 0; offset < 100; ++offset) {
    Bench b;
    b.settle(50 + offset);
    b.queue(Command{CommandCode::arm, b.cmd_seq++, kToken, 0});
    int waiting_ticks = 0;
    bool acked = false;
    for (int k = 0; k < 30 && !acked; ++k) {
      const std::size_t before = b.sent.size();
      b.tick(false);
      bool telemetry = false;
      for (std::size_t i = before; i < b.sent.size(); ++i) {
        telemetry = telemetry || is_telemetry(b.sent[i].type);
        acked = acked || b.sent[i].type == Type::command_ack;
      }
      if (acked) CHECK_FALSE(telemetry);
      if (b.vehicle.link().command_waiting()) ++waiting_ticks;
    }
    REQUIRE(acked);
    CHECK(b.last_ack()->result == AckResult::accepted);
    CHECK(b.vehicle.mode() == Mode::armed);
    if (waiting_ticks > 0) ++waited;
    longest = std::max(longest, waiting_ticks);
  }
  CHECK(waited > 0);  // some offsets met a telemetry tick
  CHECK(longest <= 7);

  // Periods that leave no tick without telemetry: the command is acted on all the same, within
  // the wait's bound.
  fw::VehicleConfig every_tick = keyed_config();
  every_tick.link.telemetry_rates_period_us = 1000;
  Bench b(every_tick);
  b.settle(50);
  b.queue(Command{CommandCode::arm, b.cmd_seq++, kToken, 0});
  while (b.vehicle.guard().queued() > 0) b.tick(false);
  int ticks = 0;
  while (b.vehicle.link().command_waiting() && ticks < 20) {
    b.tick(false);
    ++ticks;
  }
  CHECK(ticks <= 10);
  REQUIRE(b.last_ack() != nullptr);
  CHECK(b.last_ack()->result == AckResult::accepted);
  CHECK(b.vehicle.mode() == Mode::armed);
}

TEST_CASE("a KILL supersedes the commands still waiting for their tick: refused, the KILL latched") {
  int superseded = 0;
  for (int offset = 0; offset < 100; ++offset) {
    Bench b;
    b.settle(50);
    b.command(CommandCode::arm);
    b.settle(offset);
    REQUIRE(b.vehicle.mode() == Mode::armed);
    const std::uint8_t disarm_seq = b.cmd_seq;
    b.queue(Command{CommandCode::disarm, b.cmd_seq++, kToken, 0});
    while (b.vehicle.guard().queued() > 0) b.tick(false);
    b.queue(Kill{0, KillReason::operator_request});
    bool waiting_at_kill = false;
    while (b.vehicle.mode() != Mode::killed && b.vehicle.guard().queued() > 0) {
      waiting_at_kill = b.vehicle.link().command_waiting();
      b.tick(false);
    }
    b.settle(5, 0);
    CHECK(b.vehicle.mode() == Mode::killed);  // a DISARM sent before the KILL never clears it
    if (!waiting_at_kill) continue;
    ++superseded;
    const CommandAck* ack = b.last_ack();
    REQUIRE(ack != nullptr);
    CHECK(ack->seq == disarm_seq);
    CHECK(ack->result == AckResult::refused);
    CHECK(ack->reason == RefuseReason::killed);
  }
  CHECK(superseded > 0);  // the DISARM passed the guard at the start of 7 telemetry ticks
}

TEST_CASE("expect-catch is checked: its window must be sane and the vehicle flying") {
  Bench b;
  b.settle(50);
  b.command(CommandCode::expect_catch, 500);
  b.tick(true, 0);
  CHECK(b.last_ack()->reason == RefuseReason::not_flying);
  b.command(CommandCode::arm);
  b.settle(20);
  b.settle(50, kG);
  b.command(CommandCode::expect_catch, 0);
  b.tick(true, kG);
  CHECK(b.last_ack()->reason == RefuseReason::bad_argument);
  b.command(CommandCode::expect_catch, 500);
  b.settle(2, kG);  // behind this tick's heartbeat
  CHECK(b.last_ack()->result == AckResult::accepted);
}

TEST_CASE("the motors' identified lag is taken in any mode within a motor's range") {
  Bench b;
  b.settle(50);
  CHECK(b.vehicle.motor_time_constant_s() == fw::AirframeConfig{}.motor_time_constant_s);
  b.command(CommandCode::set_motor_time_constant, 55000);
  b.settle(2);
  CHECK(b.last_ack()->result == AckResult::accepted);
  CHECK(b.vehicle.motor_time_constant_s() == Approx(0.055f));
  b.command(CommandCode::set_motor_time_constant, 500000);
  b.settle(2);
  CHECK(b.last_ack()->reason == RefuseReason::bad_argument);
  CHECK(b.vehicle.motor_time_constant_s() == Approx(0.055f));
}

TEST_CASE("the vehicle's identified inertia is taken in any mode within range") {
  Bench b;
  b.settle(50);
  CHECK(b.vehicle.inertia_scale() == 1.0f);
  b.command(CommandCode::set_inertia_scale, 800);
  b.settle(2);
  CHECK(b.last_ack()->result == AckResult::accepted);
  CHECK(b.vehicle.inertia_scale() == Approx(0.8f));
  for (std::int32_t bad : {0, 499, 2001, -800}) {
    b.command(CommandCode::set_inertia_scale, bad);
    b.settle(2);
    CHECK(b.last_ack()->reason == RefuseReason::bad_argument);
  }
  CHECK(b.vehicle.inertia_scale() == Approx(0.8f));
}

namespace {
// Arm and fly a hover stream; the IMU reads the hover's specific force.
void take_off(Bench& b) {
  b.settle(50);
  b.command(CommandCode::arm);
  b.settle(20);
  b.settle(100, kG);
  REQUIRE(b.vehicle.mode() == Mode::flying);
}
// A pole landing on the plate: an 8 ms half-sine drop of the body-z specific force.
void pole_lands(Bench& b, float peak_mps2) {
  for (int i = 0; i < 8; ++i)
    b.tick(true, kG, kG - peak_mps2 * std::sin(3.14159265f * static_cast<float>(i) / 8.0f));
}
const Message* find_impact(const Bench& b, bool final) {
  for (const Message& m : b.sent)
    if (m.type == Type::impact && m.impact.final == final) return &m;
  return nullptr;
}
}  // namespace

TEST_CASE("a catch while one is expected: reported at once, not a crash, and the on-board reaction runs") {
  Bench b;
  take_off(b);
  b.command(CommandCode::expect_catch, 1000);
  b.settle(100, kG);
  const std::uint32_t onset_us = b.now_us;
  pole_lands(b, 40.0f);
  const Message* first = find_impact(b, false);
  REQUIRE(first != nullptr);
  CHECK(first->impact.classification == ImpactClass::catch_impact);
  CHECK(first->impact.vehicle_time_us >= onset_us);
  CHECK(first->impact.vehicle_time_us <= onset_us + 1000);
  CHECK(b.vehicle.catch_reaction_active());
  b.settle(30, kG);
  const Message* last = find_impact(b, true);
  REQUIRE(last != nullptr);
  CHECK(last->impact.classification == ImpactClass::catch_impact);
  CHECK(last->impact.count == first->impact.count);
  CHECK(b.vehicle.mode() == Mode::flying);

  SECTION("the ground takes over with CATCH_HANDLED") {
    b.command(CommandCode::catch_handled);
    b.tick(true, kG);
    CHECK_FALSE(b.vehicle.catch_reaction_active());
  }
  SECTION("or the reaction ends by itself") {
    b.settle(static_cast<int>(b.config.catch_reaction.duration_us / 1000), kG);
    CHECK_FALSE(b.vehicle.catch_reaction_active());
  }
}

// An impact's report, a telemetry frame and a step of the guard's check in one tick went over the
// tick's budget of 1,500 instructions (docs/hil.md): the IMPACT takes the telemetry's place.
TEST_CASE("a tick that reports an impact sends no telemetry; what was due comes a period later") {
  int impact_ticks = 0;
  for (int offset = 0; offset < 10; ++offset) {  // the impact in every phase of the task table
    Bench b;
    take_off(b);
    b.command(CommandCode::expect_catch, 1000);
    b.settle(100 + offset, kG);
    std::uint32_t last_rates_us = 0, longest_rates_gap_us = 0;
    for (int k = 0; k < 60; ++k) {
      const std::size_t before = b.sent.size();
      const float accel_z = k < 8 ? kG - 40.0f * std::sin(3.14159265f * static_cast<float>(k) / 8.0f) : kG;
      const std::uint32_t t_us = b.now_us;
      b.tick(true, kG, accel_z);
      bool impact = false, telemetry = false;
      for (std::size_t i = before; i < b.sent.size(); ++i) {
        impact = impact || b.sent[i].type == Type::impact;
        telemetry = telemetry || is_telemetry(b.sent[i].type);
        if (b.sent[i].type == Type::telemetry_rates) {
          if (last_rates_us != 0) longest_rates_gap_us = std::max(longest_rates_gap_us, t_us - last_rates_us);
          last_rates_us = t_us;
        }
      }
      if (impact) {
        ++impact_ticks;
        CHECK_FALSE(telemetry);
      }
    }
    // TELEMETRY_RATES at 100 Hz: one report skipped at most (the detection's and the final report's
    // ticks are apart by more than its period).
    CHECK(longest_rates_gap_us <= 2 * b.config.link.telemetry_rates_period_us);
    CHECK(last_rates_us != 0);
  }
  CHECK(impact_ticks >= 20);  // both reports of each impact
}

TEST_CASE("the same impact with no catch expected is reported as unexpected and starts no reaction") {
  Bench b;
  take_off(b);
  pole_lands(b, 40.0f);
  b.settle(30, kG);
  const Message* last = find_impact(b, true);
  REQUIRE(last != nullptr);
  CHECK(last->impact.classification == ImpactClass::unexpected_impact);
  CHECK_FALSE(b.vehicle.catch_reaction_active());
  CHECK(b.vehicle.mode() == Mode::flying);
}

TEST_CASE("a crash in flight stops a tumbling vehicle's motors; an upright one flies on") {
  // Upright: a dropped pole striking the vehicle, say.
  Bench upright;
  take_off(upright);
  for (int i = 0; i < 5; ++i) upright.tick(true, kG, kG + 120.0f);
  upright.settle(30, kG);
  const Message* strike = find_impact(upright, true);
  REQUIRE(strike != nullptr);
  CHECK(strike->impact.classification == ImpactClass::crash);
  CHECK(upright.vehicle.mode() == Mode::flying);
  CHECK(upright.tick(true, kG).motors_enabled);
  // Rolled past 60 degrees (10 rad/s for 0.12 s), then the impact.
  Bench b;
  take_off(b);
  b.gyro_radps = {10.0f, 0.0f, 0.0f};
  for (int i = 0; i < 120; ++i) b.tick(true, kG);
  b.gyro_radps = {};
  REQUIRE(b.vehicle.attitude().tilt_cos() < 0.5f);
  for (int i = 0; i < 5; ++i) b.tick(true, kG, kG + 120.0f);
  b.settle(30, kG);
  CHECK(b.vehicle.mode() == Mode::killed);
  CHECK(b.vehicle.failsafe_reason() == FailsafeReason::crash);
  CHECK_FALSE(b.tick(true, kG).motors_enabled);
}

TEST_CASE("the failsafe removes the tilt the accelerometer's bias gave the estimate at rest") {
  // A level vehicle whose accelerometer reads 0.4 m/s^2 too much along body x: at rest its
  // estimate leans by 2.3 degrees, which a levelled failsafe would fly.
  Bench b;
  b.accel_bias_mps2 = {0.4f, 0.0f, 0.0f};
  b.settle(3000);
  const double lean = std::atan2(0.4, kG);
  const auto tilt = [&] { return std::acos(std::min(1.0f, b.vehicle.attitude().up_in_body()[2])); };
  CHECK(tilt() == Approx(lean).epsilon(0.05));
  take_off(b);
  b.settle(6000, kG);  // held in place by the ground station: the bias is the mean body x reading
  CHECK(tilt() == Approx(lean).epsilon(0.05));
  for (int i = 0; i < 100; ++i) b.tick(true, -1);  // the setpoint stream stops: a hold, levelled
  REQUIRE(b.vehicle.mode() == Mode::hold);
  CHECK(static_cast<double>(tilt()) < 0.05 * lean);
}

TEST_CASE("LAND's descent starts from the vertical speed the ground measures, not the drifted one") {
  // In flight the accelerometer reads 0.05 m/s^2 less along up than at rest (a bias that moved):
  // over a minute the speed integrated in flight reads the hovering vehicle sinking at ~2 m/s,
  // from which the descent would climb. LAND says the vehicle is still; it sinks.
  Bench b;
  b.settle(3000);
  take_off(b);
  b.accel_bias_mps2 = {0.0f, 0.0f, -0.05f};
  const auto mean_motor = [](const fw::TickOutput& out) {
    float sum = 0;
    for (const float m : out.motor_command) sum += m;
    return sum / 4;
  };
  float hover = 0;
  for (int i = 0; i < 60000; ++i) hover = mean_motor(b.tick(true, kG));
  b.command(CommandCode::land, 0);
  REQUIRE(b.last_ack());
  CHECK(b.last_ack()->result == AckResult::accepted);
  REQUIRE(b.vehicle.mode() == Mode::failsafe_descent);
  float descending = 0;
  for (int i = 0; i < 20; ++i) descending = mean_motor(b.tick(true, -1));
  CHECK(descending < 0.95f * hover);

  b.command(CommandCode::land, kLandSpeedMax_mmps + 1);  // out of range: refused, nothing changes
  REQUIRE(b.last_ack());
  CHECK(b.last_ack()->result == AckResult::refused);
  CHECK(b.last_ack()->reason == RefuseReason::bad_argument);
}

TEST_CASE("the vehicle reports itself: heartbeats, telemetry and time-sync replies") {
  Bench b;
  b.queue(TimesyncRequest{123456, 1});
  b.settle(100);
  int heartbeats = 0, rates = 0, status = 0, replies = 0;
  for (const Message& m : b.sent) {
    if (m.type == Type::vehicle_heartbeat) {
      ++heartbeats;
      CHECK(m.node == kNode);
      CHECK(m.vehicle_heartbeat.mode == Mode::disarmed);
      CHECK((m.vehicle_heartbeat.flags & kFlagImuOk) != 0);
    }
    if (m.type == Type::telemetry_rates) ++rates;
    if (m.type == Type::telemetry_status) ++status;
    if (m.type == Type::timesync_reply) {
      ++replies;
      CHECK(m.timesync_reply.ground_time_us == 123456);
    }
  }
  CHECK(heartbeats == 5);  // 50 Hz
  CHECK(rates == 20);      // 200 Hz
  CHECK(status == 1);      // 10 Hz
  CHECK(replies == 1);
}

TEST_CASE("a broken IMU sample is not used and marks the IMU unhealthy") {
  Bench b;
  b.settle(30);
  fw::ImuSample bad;
  bad.t_us = b.now_us;
  bad.gyro_radps = {std::numeric_limits<float>::quiet_NaN(), 0, 0};
  b.vehicle.tick(bad);
  b.now_us += 1000;
  // The ARM is checked and acted on over the next ticks, all with broken samples.
  b.queue(Command{CommandCode::arm, b.cmd_seq++, kToken, 0});
  Frame f;
  bool acked = false;
  CommandAck ack{};
  Message m;
  for (int i = 0; i < pa::auth::TagCheck::kSteps; ++i) {
    bad.t_us = b.now_us;
    b.vehicle.tick(bad);
    b.now_us += 1000;
    while (b.vehicle.pop_tx(f)) {
      if (decode(f, m) == DecodeStatus::ok && m.type == Type::command_ack) {
        ack = m.command_ack;
        acked = true;
      }
    }
  }
  REQUIRE(acked);
  CHECK(ack.result == AckResult::refused);
  CHECK(ack.reason == RefuseReason::imu_unhealthy);
}

TEST_CASE("the scripted self-test flight passes on the host") {
  const fw::selftest::Result r = fw::selftest::run(nullptr);
  INFO((r.failure ? r.failure : "pass"));
  CHECK(r.pass);
  CHECK(r.impact_detection_latency_ms <= 5.0f);
  CHECK(r.failsafe_hover_after_ms <= 25.0f);
  const fw::SupervisorConfig sup{};
  CHECK(r.descent_after_ms ==
        Approx(static_cast<double>(sup.hold_max_us + sup.hover_before_descent_us) / 1000.0).margin(2.0f));
}

TEST_CASE(
    "in flight the attitude is turned onto motion capture's up; on the floor and out of range it is refused") {
  Bench b;
  b.settle(50);
  const std::int32_t tilt = tilt_argument(300, -200);  // up at (0.03, -0.02) in the vehicle's frame
  b.command(CommandCode::correct_tilt, tilt);
  CHECK(b.last_ack()->reason == RefuseReason::not_flying);
  b.command(CommandCode::arm);
  b.settle(20);
  b.settle(100, kG);
  REQUIRE(b.vehicle.mode() == Mode::flying);
  const fw::Vec3f up_before = b.vehicle.attitude().up_in_body();
  CHECK(std::fabs(up_before[0]) < 1e-3f);  // level at rest, and no rates since
  CHECK(std::fabs(up_before[1]) < 1e-3f);
  for (std::int32_t bad : {tilt_argument(2001, 0), tilt_argument(0, -2001), tilt_argument(-32768, 0)}) {
    b.command(CommandCode::correct_tilt, bad);
    CHECK(b.last_ack()->reason == RefuseReason::bad_argument);
  }
  b.command(CommandCode::correct_tilt, tilt);
  CHECK(b.last_ack()->result == AckResult::accepted);
  // The body is level in the old frame: the true up, seen from the body, leans the same way.
  const fw::Vec3f up = b.vehicle.attitude().up_in_body();
  const float n = std::sqrt(1.0f + 0.03f * 0.03f + 0.02f * 0.02f);
  CHECK(up[0] == Approx(0.03f / n).margin(1e-4));
  CHECK(up[1] == Approx(-0.02f / n).margin(1e-4));
  CHECK(up[2] == Approx(1.0f / n).margin(1e-4));
}
