// Supervisor: the transition table on its own, then the behaviour the issue asks for, driven
// at 1 kHz through the production command link: the test's ground sends encoded RATE_THRUST
// and GS_HEARTBEAT frames, and the supervisor's inputs are the link's setpoint and heartbeat
// watchdogs, as the vehicle wires them.
#include <catch2/catch.hpp>

#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "fw/command_link.hpp"
#include "fw/config.hpp"
#include "fw/supervisor.hpp"
#include "pa/protocol.hpp"
#include "pa/sequence.hpp"

namespace {

using fw::Action;
using fw::CommandResult;
using fw::Supervisor;
using fw::SupervisorInputs;
using pa::proto::CommandCode;
using pa::proto::FailsafeReason;
using pa::proto::GroundState;
using pa::proto::GsHeartbeat;
using pa::proto::Mode;
using pa::proto::RateThrust;
using pa::proto::RefuseReason;
namespace cond = fw::condition;

constexpr std::array<Mode, 8> kModes{Mode::disarmed,         Mode::armed,  Mode::flying, Mode::failsafe_hover,
                                     Mode::failsafe_descent, Mode::landed, Mode::killed, Mode::hold};

// Condition words that can occur together: take-off thrust needs a fresh setpoint, and only a
// failsafe descent can be a commanded landing.
bool consistent(Mode from, std::uint16_t c) {
  if ((c & cond::takeoff_thrust) && !(c & cond::setpoint_fresh)) return false;
  if ((c & cond::land_commanded) && from != Mode::failsafe_descent) return false;
  return true;
}

// A vehicle at 1 kHz: the ground sends setpoints every 5 ms and heartbeats every 20 ms until
// told otherwise, as frames into the vehicle's command link.
struct Bench {
  static constexpr std::uint16_t kSession = 0x5150;

  explicit Bench(std::uint32_t start_us = 5000000, fw::SupervisorConfig c = {})
      : config(c), sup(c), link(fw::LinkConfig{}, c), now_us(start_us) {}

  fw::SupervisorConfig config;
  Supervisor sup;
  fw::CommandLink link;
  std::uint32_t now_us;
  bool send_setpoints = true;
  bool repeat_sequence = false;  // frames keep coming but their sequence number is stuck
  bool send_heartbeats = true;
  float thrust_mps2 = 0.0f;
  std::uint8_t next_seq = 0;  // 4-bit setpoint sequence
  std::uint8_t heartbeat_seq = 0;
  std::uint32_t last_heartbeat_us = 0;  // when the ground's latest heartbeat arrived
  bool imu_ok = true;
  bool on_ground = false;
  bool crash = false;
  std::uint32_t ticks = 0;

  template <class M>
  void receive(const M& m, std::uint8_t node) {
    pa::proto::Frame f;
    REQUIRE(encode(m, node, f));
    link.on_frame(f, now_us);
  }
  // When the latest setpoint with a new sequence number arrived, as the link saw it.
  std::uint32_t last_fresh_us() const { return now_us - link.setpoint_age_us(now_us); }

  SupervisorInputs inputs() const {
    SupervisorInputs in;
    in.now_us = now_us;
    in.heartbeat_live = link.heartbeat_live(now_us);
    in.setpoint_fresh = link.setpoint_fresh(now_us);
    in.setpoint_thrust_mps2 = link.setpoint().thrust_mps2;
    in.imu_ok = imu_ok;
    in.on_ground = on_ground;
    in.crash = crash;
    return in;
  }
  // One 1 kHz tick: frames arrive, then the supervisor runs.
  void tick() {
    now_us += 1000u;
    ++ticks;
    if (send_setpoints && ticks % 5 == 0) {
      receive(RateThrust{{0, 0, 0}, thrust_mps2, next_seq}, link.node());
      if (!repeat_sequence) next_seq = static_cast<std::uint8_t>(pa::SetpointSeq::next(next_seq));
    }
    if (send_heartbeats && ticks % 20 == 0) {
      receive(GsHeartbeat{now_us / 1000u, kSession, GroundState::active, heartbeat_seq++},
              pa::proto::kBroadcastNode);
      REQUIRE(link.heartbeat_live(now_us));  // accepted: the bound session, an advancing sequence
      last_heartbeat_us = now_us;
    }
    sup.update(inputs());
  }
  void run_ms(int ms) {
    for (int i = 0; i < ms; ++i) tick();
  }
  // Run until the mode changes or `limit_ms` passes; returns the vehicle time of the change.
  std::uint32_t run_until_change(int limit_ms) {
    const Mode start = sup.mode();
    for (int i = 0; i < limit_ms && sup.mode() == start; ++i) tick();
    return now_us;
  }
  CommandResult command(CommandCode code) { return sup.handle_command(code, inputs()); }

  void arm() {
    thrust_mps2 = 0;
    run_ms(40);  // stream and heartbeats established
    REQUIRE(command(CommandCode::arm).accepted);
    REQUIRE(sup.mode() == Mode::armed);
  }
  void take_off() {
    arm();
    thrust_mps2 = 10;
    run_ms(10);
    REQUIRE(sup.mode() == Mode::flying);
    run_ms(100);
  }
  // Flying, then the stream stops: a hold (levelled hover) ...
  void hold() {
    take_off();
    send_setpoints = false;
    run_until_change(100);
    REQUIRE(sup.mode() == Mode::hold);
  }
  // ... which, as it lasts, is the failsafe hover.
  void hover() {
    hold();
    run_until_change(static_cast<int>(config.hold_max_us / 1000u) + 10);
    REQUIRE(sup.mode() == Mode::failsafe_hover);
  }
  void descend() {
    hover();
    run_until_change(1000);
    REQUIRE(sup.mode() == Mode::failsafe_descent);
  }
  void land_commanded() {
    take_off();
    REQUIRE(command(CommandCode::land).accepted);
    REQUIRE(sup.mode() == Mode::failsafe_descent);
  }
  void landed() {
    descend();
    on_ground = true;
    tick();
    REQUIRE(sup.mode() == Mode::landed);
    on_ground = false;
  }
  void reach(Mode m, bool land_command = false) {
    switch (m) {
      case Mode::disarmed: run_ms(40); break;
      case Mode::armed: arm(); break;
      case Mode::flying: take_off(); break;
      case Mode::hold: hold(); break;
      case Mode::failsafe_hover: hover(); break;
      case Mode::failsafe_descent: land_command ? land_commanded() : descend(); break;
      case Mode::landed: landed(); break;
      case Mode::killed:
        take_off();
        sup.kill(now_us);
        break;
    }
    REQUIRE(sup.mode() == m);
  }
};

}  // namespace

// ---------------------------------------------------------------------------------------------
// The table itself
// ---------------------------------------------------------------------------------------------

TEST_CASE("every row of the transition table can fire", "[supervisor]") {
  for (std::size_t i = 0; i < fw::kSupervisorTransitions.size(); ++i) {
    const fw::SupervisorTransition& row = fw::kSupervisorTransitions[i];
    bool reachable = false;
    for (std::uint16_t c = 0; c <= cond::kAll && !reachable; ++c)
      reachable = consistent(row.from, c) && fw::find_transition(row.from, c) == i;
    INFO("row " << i);
    CHECK(reachable);
  }
}

TEST_CASE("automatic transitions only escalate, except the ground retaking control", "[supervisor]") {
  for (const fw::SupervisorTransition& row : fw::kSupervisorTransitions) {
    INFO("from " << int(row.from) << " to " << int(row.to));
    CHECK(row.from != row.to);
    if (row.to == Mode::flying) continue;  // take-off, or the ground retakes control
    if (row.from == Mode::hold && row.to == Mode::failsafe_hover) continue;  // the same hover, now a failsafe
    CHECK(static_cast<int>(fw::action_for(row.to)) > static_cast<int>(fw::action_for(row.from)));
  }
}

TEST_CASE("modes with the motors off leave only by a command", "[supervisor]") {
  for (const fw::SupervisorTransition& row : fw::kSupervisorTransitions)
    CHECK(fw::action_for(row.from) != Action::motors_off);
  for (Mode m : {Mode::disarmed, Mode::landed, Mode::killed})
    for (std::uint16_t c = 0; c <= cond::kAll; ++c)
      REQUIRE(fw::find_transition(m, c) == fw::kSupervisorTransitions.size());
}

TEST_CASE("a crash or a lost IMU takes precedence in every mode with the motors on", "[supervisor]") {
  for (Mode m : {Mode::armed, Mode::flying, Mode::hold, Mode::failsafe_hover, Mode::failsafe_descent}) {
    for (std::uint16_t c = 0; c <= cond::kAll; ++c) {
      if (!consistent(m, c)) continue;
      const std::size_t i = fw::find_transition(m, c);
      if (c & cond::crash) {
        REQUIRE(i < fw::kSupervisorTransitions.size());
        CHECK(fw::kSupervisorTransitions[i].to == Mode::killed);
        CHECK(fw::kSupervisorTransitions[i].reason == FailsafeReason::crash);
      } else if (c & cond::imu_lost) {
        REQUIRE(i < fw::kSupervisorTransitions.size());
        CHECK(fw::kSupervisorTransitions[i].reason == FailsafeReason::imu_lost);
      }
    }
  }
}

TEST_CASE("each row, driven through update(), lands in its mode with its reason", "[supervisor]") {
  fw::SupervisorConfig config;
  config.imu_timeout_us = 0;  // the IMU debounce has its own test
  for (std::size_t i = 0; i < fw::kSupervisorTransitions.size(); ++i) {
    const fw::SupervisorTransition& row = fw::kSupervisorTransitions[i];
    std::uint16_t c = 0;
    for (; c <= cond::kAll; ++c)
      if (consistent(row.from, c) && fw::find_transition(row.from, c) == i) break;
    REQUIRE(c <= cond::kAll);
    INFO("row " << i << ", conditions 0x" << std::hex << c);

    Bench b(5000000, config);
    b.reach(row.from, (c & cond::land_commanded) != 0);
    const FailsafeReason before = b.sup.reason();
    const std::uint32_t entered_us = b.now_us - b.sup.time_in_mode_us(b.now_us);

    SupervisorInputs in;
    in.heartbeat_live = (c & cond::heartbeat_live) != 0;
    in.setpoint_fresh = (c & cond::setpoint_fresh) != 0;
    in.setpoint_thrust_mps2 = (c & cond::takeoff_thrust) ? config.takeoff_thrust_mps2 + 1.0f : 0.0f;
    in.imu_ok = (c & cond::imu_lost) == 0;
    in.on_ground = (c & cond::on_ground) != 0;
    in.crash = (c & cond::crash) != 0;
    in.now_us = entered_us + 1000u;
    if (c & cond::mode_timeout) in.now_us = entered_us + fw::mode_time_limit_us(row.from, config);
    b.sup.update(in);
    CHECK(b.sup.conditions() == c);
    CHECK(b.sup.mode() == row.to);
    CHECK(b.sup.reason() == (row.keep_reason ? before : row.reason));
    CHECK(b.sup.time_in_mode_us(in.now_us) == 0);
  }
}

// ---------------------------------------------------------------------------------------------
// Arming
// ---------------------------------------------------------------------------------------------

TEST_CASE("arming needs disarmed, a live ground heartbeat, zero thrust and a healthy IMU", "[supervisor]") {
  Bench b;
  b.run_ms(40);
  SECTION("all met: armed, motors at idle") {
    const CommandResult r = b.command(CommandCode::arm);
    CHECK(r.accepted);
    CHECK(r.reason == RefuseReason::none);
    CHECK(b.sup.mode() == Mode::armed);
    CHECK(b.sup.action() == Action::idle);
    CHECK(b.sup.motors_enabled());
  }
  SECTION("no ground heartbeat") {
    b.send_heartbeats = false;
    b.run_ms(static_cast<int>(b.config.heartbeat_timeout_us / 1000u) + 50);
    const CommandResult r = b.command(CommandCode::arm);
    CHECK_FALSE(r.accepted);
    CHECK(r.reason == RefuseReason::no_ground_heartbeat);
  }
  SECTION("a heartbeat never heard") {
    Bench silent;
    silent.send_heartbeats = false;
    silent.run_ms(40);
    CHECK(silent.command(CommandCode::arm).reason == RefuseReason::no_ground_heartbeat);
    CHECK(silent.sup.mode() == Mode::disarmed);
  }
  SECTION("thrust asked for") {
    b.thrust_mps2 = 0.5f;
    b.run_ms(10);
    const CommandResult r = b.command(CommandCode::arm);
    CHECK_FALSE(r.accepted);
    CHECK(r.reason == RefuseReason::thrust_not_zero);
  }
  SECTION("a non-finite thrust") {
    SupervisorInputs in = b.inputs();
    in.setpoint_thrust_mps2 = std::numeric_limits<float>::quiet_NaN();
    CHECK(b.sup.handle_command(CommandCode::arm, in).reason == RefuseReason::thrust_not_zero);
  }
  SECTION("an unhealthy IMU") {
    b.imu_ok = false;
    const CommandResult r = b.command(CommandCode::arm);
    CHECK_FALSE(r.accepted);
    CHECK(r.reason == RefuseReason::imu_unhealthy);
  }
  SECTION("already armed: arming is an edge, not a level") {
    REQUIRE(b.command(CommandCode::arm).accepted);
    const CommandResult r = b.command(CommandCode::arm);
    CHECK_FALSE(r.accepted);
    CHECK(r.reason == RefuseReason::not_disarmed);
    CHECK(b.sup.mode() == Mode::armed);
  }
  SECTION("killed") {
    b.sup.kill(b.now_us);
    const CommandResult r = b.command(CommandCode::arm);
    CHECK_FALSE(r.accepted);
    CHECK(r.reason == RefuseReason::killed);
    CHECK(b.sup.mode() == Mode::killed);
  }
  if (b.sup.mode() != Mode::armed) CHECK_FALSE(b.sup.motors_enabled());
}

TEST_CASE("arming is refused in every mode but disarmed", "[supervisor]") {
  for (Mode m : kModes) {
    if (m == Mode::disarmed) continue;
    Bench b;
    b.reach(m);
    b.thrust_mps2 = 0;
    const CommandResult r = b.command(CommandCode::arm);
    INFO("mode " << int(m));
    CHECK_FALSE(r.accepted);
    CHECK(r.reason == (m == Mode::killed ? RefuseReason::killed : RefuseReason::not_disarmed));
    CHECK(b.sup.mode() == m);
  }
}

TEST_CASE("only a vehicle on the ground with its motors off, not killed, may follow a new session",
          "[supervisor]") {
  for (Mode m : kModes) {
    Bench b;
    b.reach(m);
    INFO("mode " << int(m));
    CHECK(b.sup.may_follow_new_session() == (m == Mode::disarmed || m == Mode::landed));
  }
}

TEST_CASE("re-arming after landing needs a disarm first", "[supervisor]") {
  Bench b;
  b.landed();
  CHECK(b.sup.action() == Action::motors_off);
  b.send_setpoints = true;
  b.thrust_mps2 = 0;
  b.run_ms(50);
  CHECK(b.sup.mode() == Mode::landed);  // a resumed stream does not restart the motors
  CHECK(b.command(CommandCode::arm).reason == RefuseReason::not_disarmed);
  REQUIRE(b.command(CommandCode::disarm).accepted);
  CHECK(b.sup.mode() == Mode::disarmed);
  CHECK(b.sup.reason() == FailsafeReason::none);
  CHECK(b.command(CommandCode::arm).accepted);
  CHECK(b.sup.mode() == Mode::armed);
}

TEST_CASE("an armed vehicle takes off on a fresh setpoint above the take-off thrust", "[supervisor]") {
  Bench b;
  b.arm();
  b.thrust_mps2 = b.config.takeoff_thrust_mps2;  // at the threshold: still on the ground
  b.run_ms(100);
  CHECK(b.sup.mode() == Mode::armed);
  SECTION("a fresh take-off setpoint") {
    b.thrust_mps2 = 8.0f;
    b.run_ms(5);
    CHECK(b.sup.mode() == Mode::flying);
    CHECK(b.sup.action() == Action::track_setpoints);
  }
  SECTION("a stale one does not count") {
    b.send_setpoints = false;
    b.run_ms(30);
    SupervisorInputs in = b.inputs();
    in.setpoint_thrust_mps2 = 8.0f;
    REQUIRE_FALSE(in.setpoint_fresh);
    b.sup.update(in);
    CHECK(b.sup.mode() == Mode::armed);
  }
}

TEST_CASE("an armed vehicle disarms when the ground heartbeat is lost", "[supervisor]") {
  Bench b;
  b.arm();
  const std::uint32_t last_heartbeat_us = b.last_heartbeat_us;
  b.send_heartbeats = false;
  const std::uint32_t change_us = b.run_until_change(500);
  CHECK(b.sup.mode() == Mode::disarmed);
  CHECK(b.sup.reason() == FailsafeReason::heartbeat_lost);
  // The link counts a heartbeat live up to and including the timeout, so the first tick that
  // sees it lost is one 1 ms tick after it (the old test-side model said "at the timeout").
  CHECK(pa::elapsed_us(change_us, last_heartbeat_us) ==
        static_cast<std::int32_t>(b.config.heartbeat_timeout_us + 1000u));
}

// ---------------------------------------------------------------------------------------------
// Stale streams and failsafes
// ---------------------------------------------------------------------------------------------

TEST_CASE("a stale setpoint stream brings a levelled hover within 25 ms", "[supervisor]") {
  // Start close to the clock's wrap so that the failsafe timers cross it.
  Bench b(0xFFFFFFFFu - 300000u);
  b.take_off();
  SECTION("the stream stops") { b.send_setpoints = false; }
  SECTION("frames keep arriving with a repeated sequence number, heartbeats continue") {
    b.repeat_sequence = true;
  }
  // The link accepted the last new sequence number at last_fresh_us (one more frame goes out in the
  // repeated case, carrying the sequence number after it, and then sticks).
  b.run_ms(5);
  const std::uint32_t last_fresh_us = b.last_fresh_us();
  const std::uint32_t change_us = b.run_until_change(100);
  CHECK(b.sup.mode() == Mode::hold);
  CHECK(b.sup.reason() == FailsafeReason::none);  // not yet a failsafe
  CHECK(b.sup.action() == Action::level_hover);
  CHECK(b.sup.motors_enabled());
  const std::int32_t delay_us = pa::elapsed_us(change_us, last_fresh_us);
  CHECK(delay_us >= static_cast<std::int32_t>(b.config.setpoint_timeout_us));
  CHECK(delay_us <= 25000);

  // ... the same levelled hover as a failsafe once the hold lasts hold_max_us ...
  const std::uint32_t failsafe_us = b.run_until_change(1000);
  CHECK(b.sup.mode() == Mode::failsafe_hover);
  CHECK(b.sup.reason() == FailsafeReason::setpoint_stale);
  CHECK(b.sup.action() == Action::level_hover);
  CHECK(pa::elapsed_us(failsafe_us, change_us) == static_cast<std::int32_t>(b.config.hold_max_us));

  // ... then a descent after 0.5 s of hover ...
  const std::uint32_t descent_us = b.run_until_change(1000);
  CHECK(b.sup.mode() == Mode::failsafe_descent);
  CHECK(b.sup.reason() == FailsafeReason::setpoint_stale);
  CHECK(b.sup.action() == Action::descend);
  CHECK(pa::elapsed_us(descent_us, failsafe_us) >= 499000);
  CHECK(pa::elapsed_us(descent_us, failsafe_us) <= 501000);

  // ... and motors off once on the ground.
  b.run_ms(800);
  CHECK(b.sup.mode() == Mode::failsafe_descent);
  b.on_ground = true;
  b.tick();
  CHECK(b.sup.mode() == Mode::landed);
  CHECK(b.sup.reason() == FailsafeReason::setpoint_stale);
  CHECK(b.sup.action() == Action::motors_off);
  CHECK_FALSE(b.sup.motors_enabled());
}

TEST_CASE("a radio out for 100 ms is a hold that ends with the stream, never a failsafe", "[supervisor]") {
  Bench b;
  b.take_off();
  // Nothing arrives for 100 ms, both ways: no setpoints, no heartbeats.
  b.send_setpoints = false;
  b.send_heartbeats = false;
  std::vector<Mode> modes{b.sup.mode()};
  const auto watch = [&] {
    if (b.sup.mode() != modes.back()) modes.push_back(b.sup.mode());
  };
  for (int i = 0; i < 100; ++i) {
    b.tick();
    watch();
  }
  CHECK(b.sup.mode() == Mode::hold);
  CHECK(b.sup.reason() == FailsafeReason::none);
  CHECK(b.sup.action() == Action::level_hover);
  b.send_setpoints = true;
  b.send_heartbeats = true;
  for (int i = 0; i < 50; ++i) {
    b.tick();
    watch();
  }
  CHECK(modes == std::vector<Mode>{Mode::flying, Mode::hold, Mode::flying});
  CHECK(b.sup.reason() == FailsafeReason::none);
}

TEST_CASE("a hold answers LAND with the descent and refuses DISARM, as in flight", "[supervisor]") {
  Bench b;
  b.hold();
  CHECK_FALSE(b.command(CommandCode::disarm).accepted);
  CHECK(b.command(CommandCode::land).accepted);
  CHECK(b.sup.mode() == Mode::failsafe_descent);
  CHECK(b.sup.reason() == FailsafeReason::land_command);
}

TEST_CASE("a descent that never touches the ground ends by its timeout", "[supervisor]") {
  Bench b;
  b.descend();
  const std::uint32_t start_us = b.now_us;
  const std::uint32_t end_us = b.run_until_change(static_cast<int>(b.config.descent_max_us / 1000u) + 10);
  CHECK(b.sup.mode() == Mode::landed);
  CHECK(pa::elapsed_us(end_us, start_us) == static_cast<std::int32_t>(b.config.descent_max_us));
}

TEST_CASE("a lost ground heartbeat in flight brings the hover, then the descent", "[supervisor]") {
  Bench b;
  b.take_off();
  b.send_heartbeats = false;  // setpoints continue: a ground station that lost its mind
  const std::uint32_t last_heartbeat_us = b.last_heartbeat_us;
  const std::uint32_t change_us = b.run_until_change(500);
  CHECK(b.sup.mode() == Mode::failsafe_hover);
  CHECK(b.sup.reason() == FailsafeReason::heartbeat_lost);
  // The link counts a heartbeat live up to and including the timeout, so the first tick that
  // sees it lost is one 1 ms tick after it (the old test-side model said "at the timeout").
  CHECK(pa::elapsed_us(change_us, last_heartbeat_us) ==
        static_cast<std::int32_t>(b.config.heartbeat_timeout_us + 1000u));
  // Fresh setpoints alone do not end the failsafe.
  b.run_until_change(1000);
  CHECK(b.sup.mode() == Mode::failsafe_descent);
  CHECK(b.sup.reason() == FailsafeReason::heartbeat_lost);
}

TEST_CASE("the failsafe ends when the ground station retakes control", "[supervisor]") {
  Bench b;
  SECTION("from the hover") {
    b.hover();
    b.run_ms(100);
    b.send_setpoints = true;
    b.run_until_change(20);
    CHECK(b.sup.mode() == Mode::flying);
    CHECK(b.sup.reason() == FailsafeReason::none);
  }
  SECTION("from the descent") {
    b.descend();
    b.run_ms(100);
    b.send_setpoints = true;
    b.run_until_change(20);
    CHECK(b.sup.mode() == Mode::flying);
  }
  SECTION("not while the heartbeat is missing") {
    b.hover();
    b.send_heartbeats = false;
    b.run_ms(static_cast<int>(b.config.heartbeat_timeout_us / 1000u) + 50);  // it times out in the hover
    b.send_setpoints = true;
    b.run_ms(100);
    SupervisorInputs in = b.inputs();
    REQUIRE(in.setpoint_fresh);
    REQUIRE_FALSE(in.heartbeat_live);
    CHECK(b.sup.mode() == Mode::failsafe_hover);
    CHECK(b.sup.reason() == FailsafeReason::setpoint_stale);
  }
  SECTION("not from a commanded landing") {
    b.land_commanded();
    b.run_ms(200);
    CHECK(b.inputs().setpoint_fresh);
    CHECK(b.sup.mode() == Mode::failsafe_descent);
    CHECK(b.sup.reason() == FailsafeReason::land_command);
    b.on_ground = true;
    b.tick();
    CHECK(b.sup.mode() == Mode::landed);
    CHECK(b.sup.reason() == FailsafeReason::land_command);
  }
}

TEST_CASE("ground contact during the failsafe hover stops the motors", "[supervisor]") {
  Bench b;
  b.hover();
  b.on_ground = true;
  b.tick();
  CHECK(b.sup.mode() == Mode::landed);
  CHECK(b.sup.reason() == FailsafeReason::setpoint_stale);
}

TEST_CASE("LAND, DISARM and the commands that are not the supervisor's", "[supervisor]") {
  SECTION("LAND from flying or the hover starts a commanded descent") {
    for (Mode m : {Mode::flying, Mode::failsafe_hover}) {
      Bench b;
      b.reach(m);
      const CommandResult r = b.command(CommandCode::land);
      CHECK(r.accepted);
      CHECK(b.sup.mode() == Mode::failsafe_descent);
      CHECK(b.sup.reason() == FailsafeReason::land_command);
      CHECK(b.sup.time_in_mode_us(b.now_us) == 0);
    }
  }
  SECTION("LAND during a failsafe descent makes it a commanded one, timer kept") {
    Bench b;
    b.descend();
    b.run_ms(300);
    CHECK(b.command(CommandCode::land).accepted);
    CHECK(b.sup.reason() == FailsafeReason::land_command);
    CHECK(b.sup.time_in_mode_us(b.now_us) >= 300000);
    b.send_setpoints = true;
    b.run_ms(100);
    CHECK(b.sup.mode() == Mode::failsafe_descent);
  }
  SECTION("LAND on the ground is refused") {
    for (Mode m : {Mode::disarmed, Mode::armed, Mode::landed, Mode::killed}) {
      Bench b;
      b.reach(m);
      const CommandResult r = b.command(CommandCode::land);
      INFO("mode " << int(m));
      CHECK_FALSE(r.accepted);
      CHECK(r.reason == (m == Mode::killed ? RefuseReason::killed : RefuseReason::not_flying));
      CHECK(b.sup.mode() == m);
    }
  }
  SECTION("DISARM on the ground is accepted, in the air refused") {
    for (Mode m : kModes) {
      Bench b;
      b.reach(m);
      const CommandResult r = b.command(CommandCode::disarm);
      INFO("mode " << int(m));
      const bool in_air =
          m == Mode::flying || m == Mode::hold || m == Mode::failsafe_hover || m == Mode::failsafe_descent;
      CHECK(r.accepted == !in_air);
      CHECK(b.sup.mode() == (in_air ? m : Mode::disarmed));
      if (in_air) CHECK(r.reason == RefuseReason::not_disarmed);
    }
  }
  SECTION("EXPECT_CATCH and CATCH_HANDLED are refused and change nothing") {
    Bench b;
    b.take_off();
    for (CommandCode code : {CommandCode::expect_catch, CommandCode::catch_handled}) {
      const CommandResult r = b.command(code);
      CHECK_FALSE(r.accepted);
      CHECK(r.reason == RefuseReason::bad_argument);
      CHECK(b.sup.mode() == Mode::flying);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// KILL, crashes, the IMU
// ---------------------------------------------------------------------------------------------

TEST_CASE("KILL is honoured in every mode and latched until DISARM", "[supervisor]") {
  for (Mode m : kModes) {
    Bench b;
    b.reach(m);
    b.sup.kill(b.now_us);
    INFO("mode " << int(m));
    CHECK(b.sup.mode() == Mode::killed);
    CHECK(b.sup.reason() == FailsafeReason::kill);
    CHECK(b.sup.action() == Action::motors_off);
    CHECK_FALSE(b.sup.motors_enabled());
    // Nothing the link, the IMU or the stream does brings the motors back.
    b.send_setpoints = true;
    b.thrust_mps2 = 10;
    b.run_ms(200);
    CHECK(b.sup.mode() == Mode::killed);
    // DISARM clears the latch; arming is possible again.
    b.thrust_mps2 = 0;
    b.run_ms(10);
    REQUIRE(b.command(CommandCode::disarm).accepted);
    CHECK(b.sup.mode() == Mode::disarmed);
    CHECK(b.command(CommandCode::arm).accepted);
  }
}

TEST_CASE("a crash while the motors run stops them", "[supervisor]") {
  for (Mode m : {Mode::armed, Mode::flying, Mode::failsafe_hover, Mode::failsafe_descent}) {
    Bench b;
    b.reach(m);
    b.crash = true;
    b.tick();
    INFO("mode " << int(m));
    CHECK(b.sup.mode() == Mode::killed);
    CHECK(b.sup.reason() == FailsafeReason::crash);
  }
  for (Mode m : {Mode::disarmed, Mode::landed}) {
    Bench b;
    b.reach(m);
    b.crash = true;
    b.tick();
    CHECK(b.sup.mode() == m);
  }
}

TEST_CASE("a lost IMU stops the motors in the air and disarms on the ground", "[supervisor]") {
  SECTION("a single bad sample is a glitch") {
    Bench b;
    b.take_off();
    b.imu_ok = false;
    b.run_ms(static_cast<int>(b.config.imu_timeout_us / 1000u));  // bad for less than the timeout
    b.imu_ok = true;
    b.run_ms(50);
    CHECK(b.sup.mode() == Mode::flying);
  }
  SECTION("lasting IMU loss in flight") {
    Bench b;
    b.take_off();
    b.imu_ok = false;
    b.tick();
    const std::uint32_t first_bad_us = b.now_us;
    const std::uint32_t change_us = b.run_until_change(100);
    CHECK(b.sup.mode() == Mode::killed);
    CHECK(b.sup.reason() == FailsafeReason::imu_lost);
    CHECK(pa::elapsed_us(change_us, first_bad_us) == static_cast<std::int32_t>(b.config.imu_timeout_us));
  }
  SECTION("in the failsafe hover") {
    Bench b;
    b.hover();
    b.imu_ok = false;
    b.run_until_change(100);
    CHECK(b.sup.mode() == Mode::killed);
    CHECK(b.sup.reason() == FailsafeReason::imu_lost);
  }
  SECTION("armed on the ground") {
    Bench b;
    b.arm();
    b.imu_ok = false;
    b.run_until_change(100);
    CHECK(b.sup.mode() == Mode::disarmed);
    CHECK(b.sup.reason() == FailsafeReason::imu_lost);
  }
}

TEST_CASE("time in mode is wrap-safe", "[supervisor]") {
  Bench b(0xFFFFFFFFu - 2000u);
  b.arm();  // entered after the wrap
  const std::uint32_t entered_us = b.now_us;
  b.run_ms(3);
  CHECK(b.sup.time_in_mode_us(b.now_us) == 3000u);
  CHECK(b.sup.time_in_mode_us(entered_us - 1000u) == 0u);  // a clock reading from before: zero
}

TEST_CASE("time in mode saturates instead of wrapping", "[supervisor]") {
  Bench b;
  b.landed();
  b.run_ms(40 * 60 * 1000);  // 40 minutes at 1 kHz: longer than 2^31 us
  CHECK(b.sup.mode() == Mode::landed);
  CHECK(b.sup.time_in_mode_us(b.now_us) == static_cast<std::uint32_t>(Supervisor::kTimeInModeMax_us));
}
