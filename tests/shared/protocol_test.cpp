// The decoder is the most tested code in the project: a round trip for
// every frame, every malformed case rejected and counted, and random frames never crash it.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>

#include "pa/protocol.hpp"

using namespace pa::proto;

namespace {

Message decoded(const Frame& f) {
  Message m;
  REQUIRE(decode(f, m) == DecodeStatus::ok);
  return m;
}

template <class M>
Frame encoded(const M& message, std::uint8_t node = 3) {
  Frame f;
  REQUIRE(encode(message, node, f));
  return f;
}

const float kNaN = std::numeric_limits<float>::quiet_NaN();
const float kInf = std::numeric_limits<float>::infinity();

}  // namespace

TEST_CASE("identifiers put the type above the node, and a lower type wins arbitration") {
  CHECK(make_id(Type::rate_thrust, 5) == ((0x03 << 4) | 5));
  CHECK(id_type(make_id(Type::telemetry_status, 14)) == 0x13);
  CHECK(id_node(make_id(Type::telemetry_status, 14)) == 14);
  CHECK(make_id(Type::kill, 15) < make_id(Type::command, 0));
  CHECK(make_id(Type::rate_thrust, 15) < make_id(Type::telemetry_rates, 1));
}

TEST_CASE("the catalogue has one row per type, each with a legal length") {
  for (std::size_t i = 0; i < kCatalogue.size(); ++i) {
    CHECK(kCatalogue[i].length >= 1);
    CHECK(kCatalogue[i].length <= 8);
    CHECK(find_type(static_cast<std::uint8_t>(kCatalogue[i].type)) == &kCatalogue[i]);
    for (std::size_t j = i + 1; j < kCatalogue.size(); ++j) CHECK(kCatalogue[i].type != kCatalogue[j].type);
  }
}

TEST_CASE("every frame type survives a round trip") {
  SECTION("KILL") {
    const Message m = decoded(encoded(Kill{0xBEEF, KillReason::geofence}, 4));
    CHECK(m.type == Type::kill);
    CHECK(m.node == 4);
    CHECK(m.kill.session_token == 0xBEEF);
    CHECK(m.kill.reason == KillReason::geofence);
  }
  SECTION("COMMAND") {
    const Message m = decoded(encoded(Command{CommandCode::expect_catch, 200, 0x1234, -70000}));
    CHECK(m.command.code == CommandCode::expect_catch);
    CHECK(m.command.seq == 200);
    CHECK(m.command.session_token == 0x1234);
    CHECK(m.command.argument == -70000);
  }
  SECTION("RATE_THRUST") {
    const Message m = decoded(encoded(RateThrust{{1.234f, -5.678f, 0.002f}, 9.81f, 11}));
    CHECK(m.rate_thrust.rate_radps[0] == Approx(1.234f).margin(0.001));
    CHECK(m.rate_thrust.rate_radps[1] == Approx(-5.678f).margin(0.001));
    CHECK(m.rate_thrust.rate_radps[2] == Approx(0.002f).margin(0.001));
    CHECK(m.rate_thrust.thrust_mps2 == Approx(9.81f).margin(0.005));
    CHECK(m.rate_thrust.seq == 11);
  }
  SECTION("HIL_IMU_GYRO and HIL_IMU_ACCEL") {
    const Message g = decoded(encoded(HilImuGyro{{-3.1416f, 0.5f, 30.0f}, 65535}));
    CHECK(g.hil_imu_gyro.gyro_radps[0] == Approx(-3.1416f).margin(0.0005));
    CHECK(g.hil_imu_gyro.gyro_radps[2] == Approx(30.0f).margin(0.0005));
    CHECK(g.hil_imu_gyro.tick == 65535);
    const Message a = decoded(encoded(HilImuAccel{{0.1f, -45.0f, 9.81f}, 7}));
    CHECK(a.hil_imu_accel.accel_mps2[1] == Approx(-45.0f).margin(0.0025));
    CHECK(a.hil_imu_accel.accel_mps2[2] == Approx(9.81f).margin(0.0025));
    CHECK(a.hil_imu_accel.tick == 7);
  }
  SECTION("HIL_MOTORS") {
    const Message m = decoded(encoded(HilMotors{{0.0f, 0.25f, 0.5f, 1.0f}, 4242}));
    for (int i = 0; i < 4; ++i)
      CHECK(m.hil_motors.command[i] ==
            Approx(0.25f * static_cast<float>(i) + (i == 3 ? 0.25f : 0.0f)).margin(1.0 / 4095));
    CHECK(m.hil_motors.tick == 4242);
  }
  SECTION("IMPACT") {
    const Message m = decoded(encoded(Impact{0xFFFFFFF0u, 45.67f, ImpactClass::catch_impact, true, 9}));
    CHECK(m.impact.final);
    CHECK_FALSE(decoded(encoded(Impact{0, 1.0f, ImpactClass::crash, false, 0})).impact.final);
    CHECK(m.impact.vehicle_time_us == 0xFFFFFFF0u);
    CHECK(m.impact.peak_mps2 == Approx(45.67f).margin(0.005));
    CHECK(m.impact.classification == ImpactClass::catch_impact);
    CHECK(m.impact.count == 9);
  }
  SECTION("COMMAND_ACK") {
    const Message m = decoded(encoded(
        CommandAck{17, CommandCode::arm, AckResult::refused, Mode::disarmed, RefuseReason::thrust_not_zero}));
    CHECK(m.command_ack.seq == 17);
    CHECK(m.command_ack.code == CommandCode::arm);
    CHECK(m.command_ack.result == AckResult::refused);
    CHECK(m.command_ack.mode == Mode::disarmed);
    CHECK(m.command_ack.reason == RefuseReason::thrust_not_zero);
  }
  SECTION("GS_HEARTBEAT") {
    const Message m =
        decoded(encoded(GsHeartbeat{123456789u, 0xCAFE, GroundState::emergency, 255}, kBroadcastNode));
    CHECK(m.node == kBroadcastNode);
    CHECK(m.gs_heartbeat.ground_time_ms == 123456789u);
    CHECK(m.gs_heartbeat.session_token == 0xCAFE);
    CHECK(m.gs_heartbeat.state == GroundState::emergency);
    CHECK(m.gs_heartbeat.seq == 255);
  }
  SECTION("VEHICLE_HEARTBEAT") {
    const Message m = decoded(encoded(VehicleHeartbeat{
        42, Mode::failsafe_descent, kFlagArmed | kFlagSaturated, 15, FailsafeReason::heartbeat_lost, 200}));
    CHECK(m.vehicle_heartbeat.uptime_ms == 42);
    CHECK(m.vehicle_heartbeat.mode == Mode::failsafe_descent);
    CHECK(m.vehicle_heartbeat.flags == (kFlagArmed | kFlagSaturated));
    CHECK(m.vehicle_heartbeat.last_setpoint_seq == 15);
    CHECK(m.vehicle_heartbeat.failsafe == FailsafeReason::heartbeat_lost);
    CHECK(m.vehicle_heartbeat.rx_errors == 200);
  }
  SECTION("TIMESYNC_REQUEST and TIMESYNC_REPLY") {
    const Message q = decoded(encoded(TimesyncRequest{0x01020304u, 77}));
    CHECK(q.timesync_request.ground_time_us == 0x01020304u);
    CHECK(q.timesync_request.seq == 77);
    const Message r = decoded(encoded(TimesyncReply{0x01020304u, 0xA0B0C0D0u}));
    CHECK(r.timesync_reply.ground_time_us == 0x01020304u);
    CHECK(r.timesync_reply.vehicle_time_us == 0xA0B0C0D0u);
  }
  SECTION("TELEMETRY_RATES") {
    const Message m = decoded(encoded(TelemetryRates{{0.5f, -0.25f, 9.0f}, 20.0f, 0x0A}));
    CHECK(m.telemetry_rates.rate_radps[2] == Approx(9.0f).margin(0.001));
    CHECK(m.telemetry_rates.thrust_mps2 == Approx(20.0f).margin(0.005));
    CHECK(m.telemetry_rates.saturation == 0x0A);
  }
  SECTION("TELEMETRY_ATTITUDE") {
    const float s = std::sqrt(0.5f);
    const Message m = decoded(encoded(TelemetryAttitude{{s, 0.0f, -s, 0.0f}}));
    CHECK(m.telemetry_attitude.quaternion[0] == Approx(s).margin(1.0 / 32767));
    CHECK(m.telemetry_attitude.quaternion[2] == Approx(-s).margin(1.0 / 32767));
  }
  SECTION("TELEMETRY_MOTORS") {
    const Message m = decoded(encoded(TelemetryMotors{{0.1f, 0.2f, 0.3f, 0.4f}}));
    CHECK(m.telemetry_motors.command[3] == Approx(0.4f).margin(1.0 / 65535));
  }
  SECTION("TELEMETRY_STATUS") {
    const Message m = decoded(encoded(TelemetryStatus{812, 11100, 65535, 3, 2}));
    CHECK(m.telemetry_status.tick_time_max_us == 812);
    CHECK(m.telemetry_status.battery_mv == 11100);
    CHECK(m.telemetry_status.rx_errors == 65535);
    CHECK(m.telemetry_status.overruns == 3);
    CHECK(m.telemetry_status.impact_count == 2);
  }
}

TEST_CASE("encoding saturates values beyond a field's range") {
  const Message r = decoded(encoded(RateThrust{{1000.0f, -1000.0f, 0.0f}, 99.0f, 0x1F}));
  CHECK(r.rate_thrust.rate_radps[0] == Approx(32767 * kRateSetpointLsb_radps));
  CHECK(r.rate_thrust.rate_radps[1] == Approx(-32767 * kRateSetpointLsb_radps));
  CHECK(r.rate_thrust.thrust_mps2 == Approx(kThrustMax_mps2));
  CHECK(r.rate_thrust.seq == 0x0F);  // only four bits travel
  CHECK(decoded(encoded(RateThrust{{0, 0, 0}, -5.0f, 0})).rate_thrust.thrust_mps2 == 0.0f);
  CHECK(decoded(encoded(HilMotors{{-1.0f, 2.0f, 0.5f, 0.5f}, 0})).hil_motors.command[0] == 0.0f);
  CHECK(decoded(encoded(HilMotors{{-1.0f, 2.0f, 0.5f, 0.5f}, 0})).hil_motors.command[1] == 1.0f);
  CHECK(decoded(encoded(Impact{0, 1e6f, ImpactClass::crash, true, 0})).impact.peak_mps2 == Approx(655.35f));
  CHECK(decoded(encoded(HilImuAccel{{500.0f, 0, 0}, 0})).hil_imu_accel.accel_mps2[0] ==
        Approx(32767 * kAccelLsb_mps2));
}

TEST_CASE("HIL_IMU frames carry an IMU's whole range: +-2000 deg/s and +-16 g within half a bit") {
  const float gyro_full_scale_radps = 2000.0f * 3.14159265f / 180.0f;
  const float accel_full_scale_mps2 = 16.0f * 9.80665f;
  for (const float sign : {1.0f, -1.0f}) {
    const Message g = decoded(encoded(HilImuGyro{{sign * gyro_full_scale_radps, 0, 0}, 0}));
    CHECK(g.hil_imu_gyro.gyro_radps[0] == Approx(sign * gyro_full_scale_radps).margin(0.5f * kGyroLsb_radps));
    const Message a = decoded(encoded(HilImuAccel{{0, 0, sign * accel_full_scale_mps2}, 0}));
    CHECK(a.hil_imu_accel.accel_mps2[2] ==
          Approx(sign * accel_full_scale_mps2).margin(0.5f * kAccelLsb_mps2));
  }
}

TEST_CASE("encoding refuses non-finite values, bad enumerations and bad nodes, leaving the frame alone") {
  Frame f;
  f.id = 0x7AB;
  CHECK_FALSE(encode(RateThrust{{kNaN, 0, 0}, 9.81f, 1}, 1, f));
  CHECK_FALSE(encode(RateThrust{{0, 0, 0}, kInf, 1}, 1, f));
  CHECK_FALSE(encode(HilImuGyro{{0, kInf, 0}, 1}, 1, f));
  CHECK_FALSE(encode(HilImuAccel{{0, 0, -kInf}, 1}, 1, f));
  CHECK_FALSE(encode(HilMotors{{0, 0, 0, kNaN}, 1}, 1, f));
  CHECK_FALSE(encode(Impact{0, kNaN, ImpactClass::crash, false, 0}, 1, f));
  CHECK_FALSE(encode(Impact{0, 1.0f, static_cast<ImpactClass>(0), false, 0}, 1, f));
  CHECK_FALSE(encode(TelemetryAttitude{{kNaN, 0, 0, 0}}, 1, f));
  CHECK_FALSE(encode(TelemetryRates{{0, 0, 0}, kNaN, 0}, 1, f));
  CHECK_FALSE(encode(TelemetryMotors{{0, kInf, 0, 0}}, 1, f));
  CHECK_FALSE(encode(Command{static_cast<CommandCode>(0), 0, 0, 0}, 1, f));
  CHECK_FALSE(encode(Command{static_cast<CommandCode>(9), 0, 0, 0}, 1, f));
  CHECK_FALSE(encode(Kill{0, static_cast<KillReason>(9)}, 1, f));
  CHECK_FALSE(encode(GsHeartbeat{0, 0, static_cast<GroundState>(3), 0}, 1, f));
  CHECK_FALSE(
      encode(VehicleHeartbeat{0, static_cast<Mode>(kModeMax + 1), 0, 0, FailsafeReason::none, 0}, 1, f));
  CHECK_FALSE(encode(
      CommandAck{0, CommandCode::arm, static_cast<AckResult>(3), Mode::armed, RefuseReason::none}, 1, f));
  CHECK_FALSE(encode(TimesyncRequest{0, 0}, 16, f));
  CHECK(f.id == 0x7AB);
}

TEST_CASE("decoding rejects every malformed frame with its reason") {
  Message m;
  m.type = Type::telemetry_status;
  const Message untouched = m;

  SECTION("unknown types, all of them") {
    for (unsigned raw = 0; raw < 128; ++raw) {
      if (find_type(static_cast<std::uint8_t>(raw)) != nullptr) continue;
      Frame f;
      f.id = static_cast<std::uint16_t>(raw << 4 | 1);
      f.len = 8;
      CHECK(decode(f, m) == DecodeStatus::unknown_type);
    }
    Frame beyond;
    beyond.id = 0x800;  // not an 11-bit identifier
    beyond.len = 8;
    CHECK(decode(beyond, m) == DecodeStatus::unknown_type);
  }
  SECTION("every wrong length of every type") {
    for (const TypeInfo& info : kCatalogue) {
      for (std::uint8_t len = 0; len <= 15; ++len) {
        if (len == info.length) continue;
        Frame f;
        f.id = make_id(info.type, 1);
        f.len = len;
        CHECK(decode(f, m) == DecodeStatus::wrong_length);
      }
    }
  }
  SECTION("enumerations out of range") {
    auto with = [](Frame f, int byte, std::uint8_t value) {
      f.data[static_cast<std::size_t>(byte)] = value;
      return f;
    };
    const Frame kill = encoded(Kill{1, KillReason::other});
    CHECK(decode(with(kill, 2, kKillReasonMax + 1), m) == DecodeStatus::out_of_range);
    const Frame command = encoded(Command{CommandCode::arm, 1, 1, 0});
    CHECK(decode(with(command, 0, 0), m) == DecodeStatus::out_of_range);
    CHECK(decode(with(command, 0, kCommandCodeMax + 1), m) == DecodeStatus::out_of_range);
    const Frame impact = encoded(Impact{0, 1, ImpactClass::crash, false, 0});
    CHECK(decode(with(impact, 6, 0), m) == DecodeStatus::out_of_range);
    CHECK(decode(with(impact, 6, kImpactClassMax + 1), m) == DecodeStatus::out_of_range);
    // reserved bits
    CHECK(decode(with(impact, 6, kImpactFinalBit | 0x10 | 1), m) == DecodeStatus::out_of_range);
    const Frame ack =
        encoded(CommandAck{1, CommandCode::arm, AckResult::accepted, Mode::armed, RefuseReason::none});
    CHECK(decode(with(ack, 1, 0), m) == DecodeStatus::out_of_range);
    CHECK(decode(with(ack, 2, kAckResultMax + 1), m) == DecodeStatus::out_of_range);
    CHECK(decode(with(ack, 3, kModeMax + 1), m) == DecodeStatus::out_of_range);
    CHECK(decode(with(ack, 4, kRefuseReasonMax + 1), m) == DecodeStatus::out_of_range);
    const Frame gs = encoded(GsHeartbeat{0, 0, GroundState::idle, 0});
    CHECK(decode(with(gs, 6, kGroundStateMax + 1), m) == DecodeStatus::out_of_range);
    const Frame hb = encoded(VehicleHeartbeat{0, Mode::armed, 0, 0, FailsafeReason::none, 0});
    CHECK(decode(with(hb, 4, kModeMax + 1), m) == DecodeStatus::out_of_range);
    CHECK(decode(with(hb, 5, 0x80), m) == DecodeStatus::out_of_range);  // reserved flag bit
    CHECK(decode(with(hb, 6, static_cast<std::uint8_t>((kFailsafeReasonMax + 1) << 4)), m) ==
          DecodeStatus::out_of_range);
  }
  SECTION("the never-sent -32768 in a signed field") {
    for (Type t : {Type::rate_thrust, Type::hil_imu_gyro, Type::hil_imu_accel, Type::telemetry_rates,
                   Type::telemetry_attitude}) {
      Frame f;
      f.id = make_id(t, 1);
      f.len = 8;
      f.data[2] = 0x00;
      f.data[3] = 0x80;
      CHECK(decode(f, m) == DecodeStatus::out_of_range);
    }
  }
  CHECK(m.type == untouched.type);  // a rejected frame never writes the message
}

TEST_CASE("rejections are counted by reason and the counters saturate") {
  RxCounters c;
  c.count(DecodeStatus::ok);
  c.count(DecodeStatus::unknown_type);
  c.count(DecodeStatus::wrong_length);
  c.count(DecodeStatus::wrong_length);
  c.count(DecodeStatus::out_of_range);
  CHECK(c.accepted == 1);
  CHECK(c.unknown_type == 1);
  CHECK(c.wrong_length == 2);
  CHECK(c.out_of_range == 1);
  CHECK(c.rejected() == 4);
  c.wrong_length = 0xFFFFFFFFu;
  c.count(DecodeStatus::wrong_length);
  CHECK(c.wrong_length == 0xFFFFFFFFu);
}

TEST_CASE("random frames never crash the decoder, and what it accepts re-encodes to the same bytes") {
  std::mt19937 rng(20261123);
  std::uniform_int_distribution<int> byte(0, 255);
  std::uniform_int_distribution<int> id(0, 0x7FF);
  std::uniform_int_distribution<int> len(0, 8);
  int accepted = 0;
  for (int i = 0; i < 200000; ++i) {
    Frame f;
    f.id = static_cast<std::uint16_t>(id(rng));
    // Bias towards known types and right lengths so the deep paths are exercised too.
    if (i % 2 == 0) {
      const TypeInfo& info = kCatalogue[static_cast<std::size_t>(i / 2) % kCatalogue.size()];
      f.id = make_id(info.type, static_cast<std::uint8_t>(id(rng) & 0xF));
      f.len = info.length;
    } else {
      f.len = static_cast<std::uint8_t>(len(rng));
    }
    for (auto& b : f.data) b = static_cast<std::uint8_t>(byte(rng));
    Message m;
    if (decode(f, m) != DecodeStatus::ok) continue;
    ++accepted;
    Frame again;
    bool ok = false;
    switch (m.type) {
      case Type::kill: ok = encode(m.kill, m.node, again); break;
      case Type::command: ok = encode(m.command, m.node, again); break;
      case Type::rate_thrust: ok = encode(m.rate_thrust, m.node, again); break;
      case Type::hil_imu_gyro: ok = encode(m.hil_imu_gyro, m.node, again); break;
      case Type::hil_imu_accel: ok = encode(m.hil_imu_accel, m.node, again); break;
      case Type::hil_motors: ok = encode(m.hil_motors, m.node, again); break;
      case Type::auth: ok = encode(m.auth, m.node, again); break;
      case Type::link_session: ok = encode(m.link_session, m.node, again); break;
      case Type::impact: ok = encode(m.impact, m.node, again); break;
      case Type::command_ack: ok = encode(m.command_ack, m.node, again); break;
      case Type::gs_heartbeat: ok = encode(m.gs_heartbeat, m.node, again); break;
      case Type::vehicle_heartbeat: ok = encode(m.vehicle_heartbeat, m.node, again); break;
      case Type::timesync_request: ok = encode(m.timesync_request, m.node, again); break;
      case Type::timesync_reply: ok = encode(m.timesync_reply, m.node, again); break;
      case Type::telemetry_rates: ok = encode(m.telemetry_rates, m.node, again); break;
      case Type::telemetry_attitude: ok = encode(m.telemetry_attitude, m.node, again); break;
      case Type::telemetry_motors: ok = encode(m.telemetry_motors, m.node, again); break;
      case Type::telemetry_status: ok = encode(m.telemetry_status, m.node, again); break;
      case Type::hil_clock: ok = encode(m.hil_clock, m.node, again); break;
      case Type::hil_clock_done: ok = encode(m.hil_clock_done, m.node, again); break;
      case Type::hil_battery: ok = encode(m.hil_battery, m.node, again); break;
      case Type::hil_tick_cost: ok = encode(m.hil_tick_cost, m.node, again); break;
    }
    REQUIRE(ok);
    REQUIRE(again.id == f.id);
    REQUIRE(again.len == f.len);
    // Bytes beyond a type's length carry nothing; compare only the payload.
    REQUIRE(std::memcmp(again.data.data(), f.data.data(), f.len) == 0);
  }
  CHECK(accepted > 50000);
}

TEST_CASE("Every command and refusal has its name for operators; values out of range are unknown") {
  using namespace pa::proto;
  for (std::uint8_t c = 1; c <= kCommandCodeMax; ++c)
    CHECK(std::string(command_code_name(static_cast<CommandCode>(c))) != "unknown");
  CHECK(std::string(command_code_name(CommandCode::arm)) == "arm");
  CHECK(std::string(command_code_name(CommandCode::correct_tilt)) == "correct_tilt");
  CHECK(std::string(command_code_name(static_cast<CommandCode>(kCommandCodeMax + 1))) == "unknown");
  for (std::uint8_t r = 0; r <= kRefuseReasonMax; ++r)
    CHECK(std::string(refuse_reason_name(static_cast<RefuseReason>(r))) != "unknown");
  CHECK(std::string(refuse_reason_name(RefuseReason::imu_unhealthy)) == "imu_unhealthy");
  CHECK(std::string(refuse_reason_name(RefuseReason::bad_argument)) == "bad_argument");
  CHECK(std::string(refuse_reason_name(static_cast<RefuseReason>(kRefuseReasonMax + 1))) == "unknown");
}
