#include <catch2/catch.hpp>

#include "fw/command_link.hpp"

using namespace pa::proto;

namespace {

constexpr std::uint8_t kNode = 2;

struct LinkFixture {
  fw::LinkConfig link_config{};
  fw::SupervisorConfig supervisor_config{};
  fw::CommandLink link;
  LinkFixture() : link((link_config.vehicle = pa::VehicleId(kNode), link_config), supervisor_config) {}

  template <class M>
  void receive(const M& m, std::uint32_t now_us, std::uint8_t node = kNode) {
    Frame f;
    REQUIRE(encode(m, node, f));
    link.on_frame(f, now_us);
  }
  void setpoint(std::uint8_t seq, std::uint32_t now_us, float thrust = 9.81f) {
    receive(RateThrust{{0.1f, 0, 0}, thrust, seq}, now_us);
  }
  void heartbeat(std::uint8_t seq, std::uint32_t now_us, std::uint16_t token = 0x1111) {
    receive(GsHeartbeat{now_us / 1000, token, GroundState::active, seq}, now_us, kBroadcastNode);
  }
};

}  // namespace

TEST_CASE_METHOD(LinkFixture, "a setpoint stream is fresh while new sequence numbers keep arriving") {
  CHECK_FALSE(link.setpoint_fresh(0));
  CHECK(link.setpoint().thrust_mps2 == 0.0f);
  setpoint(1, 1000);
  CHECK(link.setpoint_fresh(1000));
  CHECK(link.setpoint().thrust_mps2 == Approx(9.81f).margin(0.01));
  CHECK(link.setpoint_fresh(1000 + supervisor_config.setpoint_timeout_us));
  CHECK_FALSE(link.setpoint_fresh(1001 + supervisor_config.setpoint_timeout_us));
  CHECK(link.setpoint_age_us(6000) == 5000);
}

TEST_CASE_METHOD(LinkFixture, "a stream repeating an old sequence goes stale however often it arrives") {
  setpoint(5, 0);
  for (std::uint32_t t = 1000; t <= 40000; t += 1000) setpoint(5, t);
  CHECK_FALSE(link.setpoint_fresh(40000));
  CHECK(link.counters().stale_sequence == 40);
  setpoint(3, 41000);  // behind: a replay
  CHECK_FALSE(link.setpoint_fresh(41000));
  setpoint(6, 42000);
  CHECK(link.setpoint_fresh(42000));
}

TEST_CASE_METHOD(LinkFixture, "setpoint sequences wrap from 15 to 0 and stay fresh") {
  std::uint8_t seq = 10;
  for (std::uint32_t t = 0; t < 200000; t += 5000) {
    setpoint(seq, t);
    CHECK(link.setpoint_fresh(t));
    seq = static_cast<std::uint8_t>((seq + 1) & 0x0F);
  }
  CHECK(link.counters().stale_sequence == 0);
}

TEST_CASE_METHOD(LinkFixture,
                 "ground heartbeats are live only with advancing sequences of the bound session") {
  CHECK_FALSE(link.heartbeat_live(0));
  heartbeat(1, 0);
  CHECK(link.has_session());
  CHECK(link.session_token() == 0x1111);
  CHECK(link.heartbeat_live(supervisor_config.heartbeat_timeout_us));
  CHECK_FALSE(link.heartbeat_live(supervisor_config.heartbeat_timeout_us + 1));
  heartbeat(1, 50000);  // repeated
  const std::uint32_t later_us = supervisor_config.heartbeat_timeout_us + 20000;
  CHECK_FALSE(link.heartbeat_live(later_us));

  SECTION("a disarmed vehicle follows a new ground station session") {
    heartbeat(7, later_us + 10000, 0x2222);
    CHECK(link.session_token() == 0x2222);
    CHECK(link.heartbeat_live(later_us + 10000));
  }
  SECTION("an armed vehicle ignores any other session") {
    link.set_session_rebind(false);
    heartbeat(7, later_us + 10000, 0x2222);
    CHECK(link.session_token() == 0x1111);
    CHECK_FALSE(link.heartbeat_live(later_us + 10000));
    CHECK(link.counters().foreign_session == 1);
  }
}

TEST_CASE_METHOD(LinkFixture, "KILL is latched whatever its token and taken once") {
  receive(Kill{0xDEAD, KillReason::geofence}, 0);
  KillReason reason{};
  REQUIRE(link.take_kill(reason));
  CHECK(reason == KillReason::geofence);
  CHECK_FALSE(link.take_kill(reason));
  receive(Kill{0, KillReason::operator_request}, 0, kBroadcastNode);
  CHECK(link.take_kill(reason));
}

TEST_CASE_METHOD(LinkFixture, "commands queue in order up to the capacity, the rest are counted") {
  for (std::uint8_t s = 0; s < 6; ++s) receive(Command{CommandCode::arm, s, 0x1111, 0}, 0);
  CHECK(link.counters().queue_full == 2);
  Command c{};
  for (std::uint8_t s = 0; s < fw::CommandLink::kCommandQueue; ++s) {
    REQUIRE(link.take_command(c));
    CHECK(c.seq == s);
  }
  CHECK_FALSE(link.take_command(c));
}

TEST_CASE_METHOD(LinkFixture, "frames for other vehicles are ignored, broadcasts are ours") {
  receive(RateThrust{{0, 0, 0}, 5.0f, 1}, 0, kNode + 1);
  CHECK_FALSE(link.setpoint_fresh(0));
  CHECK(link.counters().rejected() == 0);
  receive(RateThrust{{0, 0, 0}, 5.0f, 1}, 0, kBroadcastNode);
  CHECK(link.setpoint_fresh(0));
}

TEST_CASE_METHOD(LinkFixture, "malformed and misdirected frames are counted and change nothing") {
  Frame f;
  f.id = make_id(Type::rate_thrust, kNode);
  f.len = 7;
  link.on_frame(f, 0);
  f.id = static_cast<std::uint16_t>(0x7F << 4 | kNode);
  f.len = 8;
  link.on_frame(f, 0);
  receive(TelemetryStatus{1, 2, 3, 4, 5}, 0);  // a vehicle's own kind of frame
  CHECK(link.counters().wrong_length == 1);
  CHECK(link.counters().unknown_type == 1);
  CHECK(link.counters().wrong_direction == 1);
  CHECK_FALSE(link.setpoint_fresh(0));
}

TEST_CASE_METHOD(LinkFixture, "a time-sync request is kept with the time it was read") {
  receive(TimesyncRequest{777, 3}, 4242);
  TimesyncRequest r{};
  std::uint32_t at = 0;
  REQUIRE(link.take_timesync(r, at));
  CHECK(r.ground_time_us == 777);
  CHECK(at == 4242);
  CHECK_FALSE(link.take_timesync(r, at));
}

TEST_CASE_METHOD(LinkFixture, "the transmit queue keeps order and counts what does not fit") {
  constexpr std::size_t kSent = fw::CommandLink::kTxQueue + 2;
  for (std::size_t i = 0; i < kSent; ++i) {
    Frame f;
    f.id = static_cast<std::uint16_t>(i);
    CHECK(link.send(f) == (i < fw::CommandLink::kTxQueue));
  }
  CHECK(link.tx_dropped() == 2);
  Frame out;
  for (std::size_t i = 0; i < fw::CommandLink::kTxQueue; ++i) {
    REQUIRE(link.pop_tx(out));
    CHECK(out.id == i);
  }
  CHECK_FALSE(link.pop_tx(out));
}
