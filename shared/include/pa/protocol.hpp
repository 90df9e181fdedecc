// The compact CAN/radio protocol: the one source of truth for every frame both sides speak.
//
// Classic CAN, 11-bit identifiers = type[10:4] | node[3:0]; a lower type wins arbitration.
// Node 0 is the ground station, 1-14 are vehicles, 15 is broadcast. Ground-to-vehicle frames
// carry the destination node, vehicle-to-ground frames the sending vehicle. Payloads are
// little-endian, every frame is a single frame and each type has one fixed length.
//
// encode() saturates values that are out of range and refuses non-finite ones; decode()
// validates length, type, enumerations and reserved bits, never asserts, and runs in
// constant time. docs/protocol.md is the human-readable table; tests keep it in step.
//
// Freestanding: no heap, no exceptions, no OS.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace pa::proto {

// ---------------------------------------------------------------------------------------
// Frames and identifiers
// ---------------------------------------------------------------------------------------
inline constexpr std::uint8_t kMaxPayload = 8;
inline constexpr std::uint8_t kGroundNode = 0;
inline constexpr std::uint8_t kFirstVehicleNode = 1;
inline constexpr std::uint8_t kLastVehicleNode = 14;
inline constexpr std::uint8_t kBroadcastNode = 15;

struct Frame {
  std::uint16_t id = 0;  // 11-bit standard identifier
  std::uint8_t len = 0;  // data length code, 0..8
  std::array<std::uint8_t, kMaxPayload> data{};
};

enum class Type : std::uint8_t {
  kill = 0x01,
  command = 0x02,
  rate_thrust = 0x03,
  hil_imu_gyro = 0x04,
  hil_imu_accel = 0x05,
  hil_motors = 0x06,
  auth = 0x07,
  impact = 0x08,
  command_ack = 0x09,
  gs_heartbeat = 0x0A,
  vehicle_heartbeat = 0x0B,
  timesync_request = 0x0C,
  timesync_reply = 0x0D,
  link_session = 0x0E,
  telemetry_rates = 0x10,
  telemetry_attitude = 0x11,
  telemetry_motors = 0x12,
  telemetry_status = 0x13,
  hil_clock = 0x14,
  hil_clock_done = 0x15,
  hil_battery = 0x16,
  hil_tick_cost = 0x17,
};

enum class Direction : std::uint8_t {
  ground_to_vehicle,
  vehicle_to_ground,
  plant_to_vehicle,
  vehicle_to_plant,
  plant_to_ground,  // HIL only: the plant's clock, for a ground station in lockstep
  ground_to_plant
};

struct TypeInfo {
  Type type;
  const char* name;
  std::uint8_t length;
  Direction direction;
};

// The catalogue. docs/protocol.md lists the same rows (checked by tests/shared/protocol_doc_test).
inline constexpr std::array<TypeInfo, 22> kCatalogue{{
    {Type::kill, "KILL", 3, Direction::ground_to_vehicle},
    {Type::command, "COMMAND", 8, Direction::ground_to_vehicle},
    {Type::rate_thrust, "RATE_THRUST", 8, Direction::ground_to_vehicle},
    {Type::hil_imu_gyro, "HIL_IMU_GYRO", 8, Direction::plant_to_vehicle},
    {Type::hil_imu_accel, "HIL_IMU_ACCEL", 8, Direction::plant_to_vehicle},
    {Type::hil_motors, "HIL_MOTORS", 8, Direction::vehicle_to_plant},
    {Type::auth, "AUTH", 8, Direction::ground_to_vehicle},
    {Type::impact, "IMPACT", 8, Direction::vehicle_to_ground},
    {Type::command_ack, "COMMAND_ACK", 5, Direction::vehicle_to_ground},
    {Type::gs_heartbeat, "GS_HEARTBEAT", 8, Direction::ground_to_vehicle},
    {Type::vehicle_heartbeat, "VEHICLE_HEARTBEAT", 8, Direction::vehicle_to_ground},
    {Type::timesync_request, "TIMESYNC_REQUEST", 5, Direction::ground_to_vehicle},
    {Type::timesync_reply, "TIMESYNC_REPLY", 8, Direction::vehicle_to_ground},
    {Type::link_session, "LINK_SESSION", 8, Direction::vehicle_to_ground},
    {Type::telemetry_rates, "TELEMETRY_RATES", 8, Direction::vehicle_to_ground},
    {Type::telemetry_attitude, "TELEMETRY_ATTITUDE", 8, Direction::vehicle_to_ground},
    {Type::telemetry_motors, "TELEMETRY_MOTORS", 8, Direction::vehicle_to_ground},
    {Type::telemetry_status, "TELEMETRY_STATUS", 8, Direction::vehicle_to_ground},
    {Type::hil_clock, "HIL_CLOCK", 8, Direction::plant_to_ground},
    {Type::hil_clock_done, "HIL_CLOCK_DONE", 4, Direction::ground_to_plant},
    {Type::hil_battery, "HIL_BATTERY", 2, Direction::plant_to_vehicle},
    {Type::hil_tick_cost, "HIL_TICK_COST", 6, Direction::vehicle_to_plant},
}};

// Constant-time lookup: the 7-bit type indexes a table built at compile time.
namespace detail {
inline constexpr std::uint8_t kNoEntry = 0xFF;
constexpr std::array<std::uint8_t, 128> make_index() {
  std::array<std::uint8_t, 128> index{};
  for (auto& i : index) i = kNoEntry;
  for (std::size_t k = 0; k < kCatalogue.size(); ++k)
    index[static_cast<std::uint8_t>(kCatalogue[k].type)] = static_cast<std::uint8_t>(k);
  return index;
}
inline constexpr std::array<std::uint8_t, 128> kIndex = make_index();
}  // namespace detail

constexpr const TypeInfo* find_type(std::uint8_t raw_type) {
  if (raw_type >= 128) return nullptr;
  const std::uint8_t k = detail::kIndex[raw_type];
  return k == detail::kNoEntry ? nullptr : &kCatalogue[k];
}

constexpr std::uint16_t make_id(Type type, std::uint8_t node) {
  return static_cast<std::uint16_t>((static_cast<std::uint16_t>(type) << 4) | (node & 0x0Fu));
}
constexpr std::uint8_t id_type(std::uint16_t id) { return static_cast<std::uint8_t>((id >> 4) & 0x7Fu); }
constexpr std::uint8_t id_node(std::uint16_t id) { return static_cast<std::uint8_t>(id & 0x0Fu); }

// ---------------------------------------------------------------------------------------
// Scales (the unit of one least-significant bit)
// ---------------------------------------------------------------------------------------
inline constexpr float kRateSetpointLsb_radps = 0.002f;  // RATE_THRUST, TELEMETRY_RATES
inline constexpr float kThrustLsb_mps2 = 0.01f;          // 12-bit collective thrust
inline constexpr float kThrustMax_mps2 = 4095 * kThrustLsb_mps2;
inline constexpr float kGyroLsb_radps = 0.0011f;  // HIL_IMU_GYRO: +-36.04 rad/s, over an IMU's +-2000 deg/s
inline constexpr float kAccelLsb_mps2 = 0.005f;   // HIL_IMU_ACCEL
inline constexpr float kImpactPeakLsb_mps2 = 0.01f;       // IMPACT peak
inline constexpr float kQuaternionLsb = 1.0f / 32767.0f;  // TELEMETRY_ATTITUDE
inline constexpr std::uint16_t kMotorMax12 = 4095;        // HIL_MOTORS, 12-bit per motor
inline constexpr std::uint16_t kMotorMax16 = 65535;       // TELEMETRY_MOTORS, 16-bit per motor

// ---------------------------------------------------------------------------------------
// Enumerations carried in frames
// ---------------------------------------------------------------------------------------
enum class CommandCode : std::uint8_t {
  arm = 1,     // needs disarmed, a live ground heartbeat and zero thrust
  disarm = 2,  // motors off; also clears a latched KILL
  // argument: the vehicle's vertical speed as motion capture measures it, in mm/s (within
  // +-kLandSpeedMax_mmps), which the on-board descent starts from; controlled descent, then motors
  // off on the ground
  land = 3,
  expect_catch = 4,   // argument: catch window in ms; impacts inside it are catches
  catch_handled = 5,  // the ground station has taken over after an impact
  // argument: the motors' identified time constant in us (10000..100000), which the firmware
  // equalises to its airframe's (fw/motor_lag_equaliser.hpp); any mode
  set_motor_time_constant = 6,
  // argument: the vehicle's roll and pitch inertia over its airframe file's, identified, in per
  // mille (500..2000), which the rate loop takes as its inertia (fw/rate_controller.hpp); any mode
  set_inertia_scale = 7,
  // argument: where up truly lies in the on-board attitude's inertial frame, as motion capture
  // measures it: x in the high 16 bits, y in the low, signed, in 1e-4 (each within +-0.2); the
  // firmware turns its estimate onto it (fw::AttitudeEstimator::correct_tilt); flying only
  correct_tilt = 8,
};
inline constexpr std::uint8_t kCommandCodeMax = 8;
inline constexpr std::int32_t kLandSpeedMax_mmps = 5000;  // LAND's argument
// correct_tilt's argument from the true up's x and y, and back (kTiltUnit per count).
inline constexpr float kTiltUnit = 1e-4f;
inline constexpr std::int32_t kTiltMaxCounts = 2000;
constexpr std::int32_t tilt_argument(std::int16_t x_counts, std::int16_t y_counts) {
  return static_cast<std::int32_t>((static_cast<std::uint32_t>(static_cast<std::uint16_t>(x_counts)) << 16) |
                                   static_cast<std::uint16_t>(y_counts));
}
constexpr std::int16_t tilt_x_counts(std::int32_t argument) {
  return static_cast<std::int16_t>(static_cast<std::uint16_t>(static_cast<std::uint32_t>(argument) >> 16));
}
constexpr std::int16_t tilt_y_counts(std::int32_t argument) {
  return static_cast<std::int16_t>(
      static_cast<std::uint16_t>(static_cast<std::uint32_t>(argument) & 0xFFFFu));
}

enum class AckResult : std::uint8_t { accepted = 0, refused = 1, duplicate = 2 };
inline constexpr std::uint8_t kAckResultMax = 2;

enum class RefuseReason : std::uint8_t {
  none = 0,
  not_disarmed = 1,
  no_ground_heartbeat = 2,
  thrust_not_zero = 3,
  bad_session_token = 4,
  imu_unhealthy = 5,
  killed = 6,
  not_flying = 7,
  bad_argument = 8,
};
inline constexpr std::uint8_t kRefuseReasonMax = 8;

// Names for logs and operators ("arm", "imu_unhealthy"); "unknown" out of range.
constexpr const char* command_code_name(CommandCode code) {
  switch (code) {
    case CommandCode::arm: return "arm";
    case CommandCode::disarm: return "disarm";
    case CommandCode::land: return "land";
    case CommandCode::expect_catch: return "expect_catch";
    case CommandCode::catch_handled: return "catch_handled";
    case CommandCode::set_motor_time_constant: return "set_motor_time_constant";
    case CommandCode::set_inertia_scale: return "set_inertia_scale";
    case CommandCode::correct_tilt: return "correct_tilt";
  }
  return "unknown";
}
constexpr const char* refuse_reason_name(RefuseReason reason) {
  switch (reason) {
    case RefuseReason::none: return "none";
    case RefuseReason::not_disarmed: return "not_disarmed";
    case RefuseReason::no_ground_heartbeat: return "no_ground_heartbeat";
    case RefuseReason::thrust_not_zero: return "thrust_not_zero";
    case RefuseReason::bad_session_token: return "bad_session_token";
    case RefuseReason::imu_unhealthy: return "imu_unhealthy";
    case RefuseReason::killed: return "killed";
    case RefuseReason::not_flying: return "not_flying";
    case RefuseReason::bad_argument: return "bad_argument";
  }
  return "unknown";
}

// Vehicle modes, as the supervisor reports them. hold is the setpoint stream paused (a radio
// fading): the vehicle levels and hovers on board and follows the stream again when it resumes;
// it is not a failsafe until it lasts (firmware/core/include/fw/supervisor.hpp).
enum class Mode : std::uint8_t {
  disarmed = 0,
  armed = 1,
  flying = 2,
  failsafe_hover = 3,
  failsafe_descent = 4,
  landed = 5,
  killed = 6,
  hold = 7,
};
inline constexpr std::uint8_t kModeMax = 7;

// The mode's name in logs and tools ("mode N" is never needed: decoding rejects other values).
constexpr const char* mode_name(Mode mode) {
  switch (mode) {
    case Mode::disarmed: return "disarmed";
    case Mode::armed: return "armed";
    case Mode::flying: return "flying";
    case Mode::failsafe_hover: return "failsafe_hover";
    case Mode::failsafe_descent: return "failsafe_descent";
    case Mode::landed: return "landed";
    case Mode::killed: return "killed";
    case Mode::hold: return "hold";
  }
  return "unknown";
}

// Why the vehicle is in a failsafe (or why it stopped); 4 bits on the wire.
enum class FailsafeReason : std::uint8_t {
  none = 0,
  setpoint_stale = 1,
  heartbeat_lost = 2,
  imu_lost = 3,
  land_command = 4,
  kill = 5,
  crash = 6,
};
inline constexpr std::uint8_t kFailsafeReasonMax = 6;

enum class KillReason : std::uint8_t {
  operator_request = 0,
  geofence = 1,
  estimator = 2,
  crash = 3,
  other = 4
};
inline constexpr std::uint8_t kKillReasonMax = 4;

enum class ImpactClass : std::uint8_t { catch_impact = 1, crash = 2, unexpected_impact = 3 };
inline constexpr std::uint8_t kImpactClassMin = 1;
inline constexpr std::uint8_t kImpactClassMax = 3;

// Ground-station states broadcast in GS_HEARTBEAT.
enum class GroundState : std::uint8_t { idle = 0, active = 1, emergency = 2 };
inline constexpr std::uint8_t kGroundStateMax = 2;

// VEHICLE_HEARTBEAT flag bits.
inline constexpr std::uint8_t kFlagArmed = 1u << 0;
inline constexpr std::uint8_t kFlagImuOk = 1u << 1;
inline constexpr std::uint8_t kFlagGroundHeartbeatOk = 1u << 2;
inline constexpr std::uint8_t kFlagSetpointFresh = 1u << 3;
inline constexpr std::uint8_t kFlagCatchExpected = 1u << 4;
inline constexpr std::uint8_t kFlagImpactReaction = 1u << 5;
inline constexpr std::uint8_t kFlagSaturated = 1u << 6;
inline constexpr std::uint8_t kVehicleFlagsMask = 0x7F;

// ---------------------------------------------------------------------------------------
// Messages, in physical units
// ---------------------------------------------------------------------------------------
struct Kill {
  std::uint16_t session_token;
  KillReason reason;
};
struct Command {
  CommandCode code;
  std::uint8_t seq;  // 8-bit command sequence
  std::uint16_t session_token;
  std::int32_t argument;
};
struct RateThrust {
  std::array<float, 3> rate_radps;  // body rates, +-65.534 rad/s
  float thrust_mps2;                // mass-normalised collective thrust a_q, 0..40.95 m/s^2
  std::uint8_t seq;                 // 4-bit setpoint sequence
};
struct HilImuGyro {
  std::array<float, 3> gyro_radps;  // +-36.04 rad/s (kGyroLsb_radps)
  std::uint16_t tick;
};
struct HilImuAccel {
  std::array<float, 3> accel_mps2;  // specific force, body frame, +-163.8 m/s^2
  std::uint16_t tick;
};
struct HilMotors {
  std::array<float, 4> command;  // normalised 0..1 per motor, 12-bit on the wire
  std::uint16_t tick;
};
struct Impact {
  std::uint32_t vehicle_time_us;  // the impact's onset
  float peak_mps2;                // 0..655.35 m/s^2
  ImpactClass classification;
  bool final;          // false: sent on detection (provisional class); true: the event is over
  std::uint8_t count;  // impacts since boot, wrapping; both reports of one impact share it
};
inline constexpr std::uint8_t kImpactFinalBit = 0x80;
struct CommandAck {
  std::uint8_t seq;
  CommandCode code;
  AckResult result;
  Mode mode;
  RefuseReason reason;
};
struct GsHeartbeat {
  std::uint32_t ground_time_ms;
  std::uint16_t session_token;
  GroundState state;
  std::uint8_t seq;
};
struct VehicleHeartbeat {
  std::uint32_t uptime_ms;
  Mode mode;
  std::uint8_t flags;              // kFlag* bits
  std::uint8_t last_setpoint_seq;  // 4 bits
  FailsafeReason failsafe;         // 4 bits
  std::uint8_t rx_errors;          // saturating count of rejected frames
};
// The tag of the ground frame sent just before it (pa/link_auth.hpp).
struct Auth {
  std::uint16_t counter_low;  // the low 16 bits of the frame's counter
  std::uint64_t tag;          // 48-bit truncated MAC
};
// The vehicle's link session: the nonce drawn at boot and the last counter it accepted.
struct LinkSession {
  std::uint32_t nonce;
  std::uint32_t last_counter;
};
struct TimesyncRequest {
  std::uint32_t ground_time_us;
  std::uint8_t seq;
};
struct TimesyncReply {
  std::uint32_t ground_time_us;   // echoed from the request
  std::uint32_t vehicle_time_us;  // when the request was read
};
struct TelemetryRates {
  std::array<float, 3> rate_radps;  // measured body rates
  float thrust_mps2;                // collective thrust applied
  std::uint8_t saturation;          // 4 bits: roll, pitch, collective, yaw not fully allocated
};
struct TelemetryAttitude {
  std::array<float, 4> quaternion;  // w, x, y, z of the on-board attitude estimate
};
struct TelemetryMotors {
  std::array<float, 4> command;  // normalised 0..1, 16-bit on the wire
};
// HIL lockstep with the ground station (docs/hil.md): the plant's step and how many
// motion-capture frames it has published by then; the ground station's answer once it has
// stepped to that time.
struct HilClock {
  std::uint32_t step;          // the plant's time in IMU periods (1 ms)
  std::uint32_t mocap_frames;  // frames published so far: the newest is frame_number mocap_frames - 1
};
struct HilClockDone {
  std::uint32_t step;
};
// The battery's terminal voltage under load as the plant has it (what a vehicle's ADC reads).
struct HilBattery {
  std::uint16_t voltage_mv;  // 0..65.535 V
};
// What one tick of an emulated flight image cost, in guest instructions (processor in the loop:
// the image counts them exactly under QEMU's -icount). Sent just before the tick's HIL_MOTORS.
struct HilTickCost {
  std::uint16_t tick;  // as in HIL_MOTORS
  std::uint32_t instructions;
};
struct TelemetryStatus {
  std::uint16_t tick_time_max_us;  // longest 1 kHz tick since the last report
  std::uint16_t battery_mv;
  std::uint16_t rx_errors;  // total rejected frames, saturating
  std::uint8_t overruns;    // ticks that missed their deadline, saturating
  std::uint8_t impact_count;
};

// A decoded frame: the type tells which member is valid.
struct Message {
  Type type = Type::kill;
  std::uint8_t node = 0;
  union {
    Kill kill;
    Command command;
    RateThrust rate_thrust;
    HilImuGyro hil_imu_gyro;
    HilImuAccel hil_imu_accel;
    HilMotors hil_motors;
    Auth auth;
    Impact impact;
    CommandAck command_ack;
    GsHeartbeat gs_heartbeat;
    VehicleHeartbeat vehicle_heartbeat;
    TimesyncRequest timesync_request;
    TimesyncReply timesync_reply;
    LinkSession link_session;
    TelemetryRates telemetry_rates;
    TelemetryAttitude telemetry_attitude;
    TelemetryMotors telemetry_motors;
    TelemetryStatus telemetry_status;
    HilClock hil_clock;
    HilClockDone hil_clock_done;
    HilBattery hil_battery;
    HilTickCost hil_tick_cost;
  };
  Message() : kill{} {}
};

enum class DecodeStatus : std::uint8_t { ok = 0, unknown_type, wrong_length, out_of_range };

// ---------------------------------------------------------------------------------------
// Byte helpers
// ---------------------------------------------------------------------------------------
namespace detail {
inline void put_u16(std::uint8_t* p, std::uint16_t v) {
  p[0] = static_cast<std::uint8_t>(v);
  p[1] = static_cast<std::uint8_t>(v >> 8);
}
inline void put_u32(std::uint8_t* p, std::uint32_t v) {
  put_u16(p, static_cast<std::uint16_t>(v));
  put_u16(p + 2, static_cast<std::uint16_t>(v >> 16));
}
inline std::uint16_t get_u16(const std::uint8_t* p) { return static_cast<std::uint16_t>(p[0] | (p[1] << 8)); }
inline std::uint32_t get_u32(const std::uint8_t* p) {
  return static_cast<std::uint32_t>(get_u16(p)) | (static_cast<std::uint32_t>(get_u16(p + 2)) << 16);
}
inline bool finite(float v) { return std::isfinite(v); }

// Round to the nearest count and saturate to [lo, hi]. The caller has checked finiteness.
inline std::int32_t quantise(float value, float lsb, std::int32_t lo, std::int32_t hi) {
  const float counts = value / lsb;
  if (counts <= static_cast<float>(lo)) return lo;
  if (counts >= static_cast<float>(hi)) return hi;
  // Round half away from zero without a libm call (cheap on the MCU).
  return static_cast<std::int32_t>(counts + (counts >= 0.0f ? 0.5f : -0.5f));
}
inline void put_scaled_i16(std::uint8_t* p, float value, float lsb) {
  put_u16(p, static_cast<std::uint16_t>(static_cast<std::int16_t>(quantise(value, lsb, -32767, 32767))));
}
inline float get_scaled_i16(const std::uint8_t* p, float lsb) {
  return static_cast<float>(static_cast<std::int16_t>(get_u16(p))) * lsb;
}
template <std::size_t N>
inline bool all_finite(const std::array<float, N>& v) {
  bool ok = true;
  for (float x : v) ok = ok && finite(x);
  return ok;
}
inline Frame start(Type type, std::uint8_t node) {
  Frame f;
  f.id = make_id(type, node);
  f.len = find_type(static_cast<std::uint8_t>(type))->length;
  return f;
}
}  // namespace detail

// ---------------------------------------------------------------------------------------
// Encoding: returns false (and leaves `out` untouched) when a value is not finite or a
// node is out of range; otherwise saturates every field to its range.
// ---------------------------------------------------------------------------------------
inline bool valid_node(std::uint8_t node) { return node <= kBroadcastNode; }

inline bool encode(const Kill& m, std::uint8_t node, Frame& out) {
  if (!valid_node(node) || static_cast<std::uint8_t>(m.reason) > kKillReasonMax) return false;
  Frame f = detail::start(Type::kill, node);
  detail::put_u16(&f.data[0], m.session_token);
  f.data[2] = static_cast<std::uint8_t>(m.reason);
  out = f;
  return true;
}

inline bool encode(const Command& m, std::uint8_t node, Frame& out) {
  const auto code = static_cast<std::uint8_t>(m.code);
  if (!valid_node(node) || code == 0 || code > kCommandCodeMax) return false;
  Frame f = detail::start(Type::command, node);
  f.data[0] = code;
  f.data[1] = m.seq;
  detail::put_u16(&f.data[2], m.session_token);
  detail::put_u32(&f.data[4], static_cast<std::uint32_t>(m.argument));
  out = f;
  return true;
}

inline bool encode(const RateThrust& m, std::uint8_t node, Frame& out) {
  if (!valid_node(node) || !detail::all_finite(m.rate_radps) || !detail::finite(m.thrust_mps2)) return false;
  Frame f = detail::start(Type::rate_thrust, node);
  for (int i = 0; i < 3; ++i) detail::put_scaled_i16(&f.data[2 * i], m.rate_radps[i], kRateSetpointLsb_radps);
  const auto thrust = static_cast<std::uint16_t>(detail::quantise(m.thrust_mps2, kThrustLsb_mps2, 0, 4095));
  detail::put_u16(&f.data[6], static_cast<std::uint16_t>(thrust | ((m.seq & 0x0Fu) << 12)));
  out = f;
  return true;
}

inline bool encode(const HilImuGyro& m, std::uint8_t node, Frame& out) {
  if (!valid_node(node) || !detail::all_finite(m.gyro_radps)) return false;
  Frame f = detail::start(Type::hil_imu_gyro, node);
  for (int i = 0; i < 3; ++i) detail::put_scaled_i16(&f.data[2 * i], m.gyro_radps[i], kGyroLsb_radps);
  detail::put_u16(&f.data[6], m.tick);
  out = f;
  return true;
}

inline bool encode(const HilImuAccel& m, std::uint8_t node, Frame& out) {
  if (!valid_node(node) || !detail::all_finite(m.accel_mps2)) return false;
  Frame f = detail::start(Type::hil_imu_accel, node);
  for (int i = 0; i < 3; ++i) detail::put_scaled_i16(&f.data[2 * i], m.accel_mps2[i], kAccelLsb_mps2);
  detail::put_u16(&f.data[6], m.tick);
  out = f;
  return true;
}

inline bool encode(const HilMotors& m, std::uint8_t node, Frame& out) {
  if (!valid_node(node) || !detail::all_finite(m.command)) return false;
  Frame f = detail::start(Type::hil_motors, node);
  std::uint64_t bits = 0;
  for (int i = 0; i < 4; ++i) {
    const auto c =
        static_cast<std::uint64_t>(detail::quantise(m.command[i], 1.0f / kMotorMax12, 0, kMotorMax12));
    bits |= c << (12 * i);
  }
  for (int i = 0; i < 6; ++i) f.data[i] = static_cast<std::uint8_t>(bits >> (8 * i));
  detail::put_u16(&f.data[6], m.tick);
  out = f;
  return true;
}

inline bool encode(const Auth& m, std::uint8_t node, Frame& out) {
  if (!valid_node(node) || m.tag > 0xFFFFFFFFFFFFull) return false;
  Frame f = detail::start(Type::auth, node);
  detail::put_u16(&f.data[0], m.counter_low);
  detail::put_u32(&f.data[2], static_cast<std::uint32_t>(m.tag));
  detail::put_u16(&f.data[6], static_cast<std::uint16_t>(m.tag >> 32));
  out = f;
  return true;
}

inline bool encode(const LinkSession& m, std::uint8_t node, Frame& out) {
  if (!valid_node(node)) return false;
  Frame f = detail::start(Type::link_session, node);
  detail::put_u32(&f.data[0], m.nonce);
  detail::put_u32(&f.data[4], m.last_counter);
  out = f;
  return true;
}

inline bool encode(const Impact& m, std::uint8_t node, Frame& out) {
  const auto cls = static_cast<std::uint8_t>(m.classification);
  if (!valid_node(node) || !detail::finite(m.peak_mps2) || cls < kImpactClassMin || cls > kImpactClassMax)
    return false;
  Frame f = detail::start(Type::impact, node);
  detail::put_u32(&f.data[0], m.vehicle_time_us);
  detail::put_u16(&f.data[4],
                  static_cast<std::uint16_t>(detail::quantise(m.peak_mps2, kImpactPeakLsb_mps2, 0, 65535)));
  f.data[6] = static_cast<std::uint8_t>(cls | (m.final ? kImpactFinalBit : 0u));
  f.data[7] = m.count;
  out = f;
  return true;
}

inline bool encode(const CommandAck& m, std::uint8_t node, Frame& out) {
  const auto code = static_cast<std::uint8_t>(m.code);
  if (!valid_node(node) || code == 0 || code > kCommandCodeMax ||
      static_cast<std::uint8_t>(m.result) > kAckResultMax || static_cast<std::uint8_t>(m.mode) > kModeMax ||
      static_cast<std::uint8_t>(m.reason) > kRefuseReasonMax)
    return false;
  Frame f = detail::start(Type::command_ack, node);
  f.data[0] = m.seq;
  f.data[1] = code;
  f.data[2] = static_cast<std::uint8_t>(m.result);
  f.data[3] = static_cast<std::uint8_t>(m.mode);
  f.data[4] = static_cast<std::uint8_t>(m.reason);
  out = f;
  return true;
}

inline bool encode(const GsHeartbeat& m, std::uint8_t node, Frame& out) {
  if (!valid_node(node) || static_cast<std::uint8_t>(m.state) > kGroundStateMax) return false;
  Frame f = detail::start(Type::gs_heartbeat, node);
  detail::put_u32(&f.data[0], m.ground_time_ms);
  detail::put_u16(&f.data[4], m.session_token);
  f.data[6] = static_cast<std::uint8_t>(m.state);
  f.data[7] = m.seq;
  out = f;
  return true;
}

inline bool encode(const VehicleHeartbeat& m, std::uint8_t node, Frame& out) {
  if (!valid_node(node) || static_cast<std::uint8_t>(m.mode) > kModeMax ||
      static_cast<std::uint8_t>(m.failsafe) > kFailsafeReasonMax)
    return false;
  Frame f = detail::start(Type::vehicle_heartbeat, node);
  detail::put_u32(&f.data[0], m.uptime_ms);
  f.data[4] = static_cast<std::uint8_t>(m.mode);
  f.data[5] = static_cast<std::uint8_t>(m.flags & kVehicleFlagsMask);
  f.data[6] =
      static_cast<std::uint8_t>((m.last_setpoint_seq & 0x0Fu) | (static_cast<std::uint8_t>(m.failsafe) << 4));
  f.data[7] = m.rx_errors;
  out = f;
  return true;
}

inline bool encode(const TimesyncRequest& m, std::uint8_t node, Frame& out) {
  if (!valid_node(node)) return false;
  Frame f = detail::start(Type::timesync_request, node);
  detail::put_u32(&f.data[0], m.ground_time_us);
  f.data[4] = m.seq;
  out = f;
  return true;
}

inline bool encode(const TimesyncReply& m, std::uint8_t node, Frame& out) {
  if (!valid_node(node)) return false;
  Frame f = detail::start(Type::timesync_reply, node);
  detail::put_u32(&f.data[0], m.ground_time_us);
  detail::put_u32(&f.data[4], m.vehicle_time_us);
  out = f;
  return true;
}

inline bool encode(const TelemetryRates& m, std::uint8_t node, Frame& out) {
  if (!valid_node(node) || !detail::all_finite(m.rate_radps) || !detail::finite(m.thrust_mps2)) return false;
  Frame f = detail::start(Type::telemetry_rates, node);
  for (int i = 0; i < 3; ++i) detail::put_scaled_i16(&f.data[2 * i], m.rate_radps[i], kRateSetpointLsb_radps);
  const auto thrust = static_cast<std::uint16_t>(detail::quantise(m.thrust_mps2, kThrustLsb_mps2, 0, 4095));
  detail::put_u16(&f.data[6], static_cast<std::uint16_t>(thrust | ((m.saturation & 0x0Fu) << 12)));
  out = f;
  return true;
}

inline bool encode(const TelemetryAttitude& m, std::uint8_t node, Frame& out) {
  if (!valid_node(node) || !detail::all_finite(m.quaternion)) return false;
  Frame f = detail::start(Type::telemetry_attitude, node);
  for (int i = 0; i < 4; ++i) detail::put_scaled_i16(&f.data[2 * i], m.quaternion[i], kQuaternionLsb);
  out = f;
  return true;
}

inline bool encode(const TelemetryMotors& m, std::uint8_t node, Frame& out) {
  if (!valid_node(node) || !detail::all_finite(m.command)) return false;
  Frame f = detail::start(Type::telemetry_motors, node);
  for (int i = 0; i < 4; ++i)
    detail::put_u16(&f.data[2 * i], static_cast<std::uint16_t>(
                                        detail::quantise(m.command[i], 1.0f / kMotorMax16, 0, kMotorMax16)));
  out = f;
  return true;
}

inline bool encode(const TelemetryStatus& m, std::uint8_t node, Frame& out) {
  if (!valid_node(node)) return false;
  Frame f = detail::start(Type::telemetry_status, node);
  detail::put_u16(&f.data[0], m.tick_time_max_us);
  detail::put_u16(&f.data[2], m.battery_mv);
  detail::put_u16(&f.data[4], m.rx_errors);
  f.data[6] = m.overruns;
  f.data[7] = m.impact_count;
  out = f;
  return true;
}

inline bool encode(const HilClock& m, std::uint8_t node, Frame& out) {
  if (!valid_node(node)) return false;
  Frame f = detail::start(Type::hil_clock, node);
  detail::put_u32(&f.data[0], m.step);
  detail::put_u32(&f.data[4], m.mocap_frames);
  out = f;
  return true;
}

inline bool encode(const HilClockDone& m, std::uint8_t node, Frame& out) {
  if (!valid_node(node)) return false;
  Frame f = detail::start(Type::hil_clock_done, node);
  detail::put_u32(&f.data[0], m.step);
  out = f;
  return true;
}

inline bool encode(const HilBattery& m, std::uint8_t node, Frame& out) {
  if (!valid_node(node)) return false;
  Frame f = detail::start(Type::hil_battery, node);
  detail::put_u16(&f.data[0], m.voltage_mv);
  out = f;
  return true;
}

inline bool encode(const HilTickCost& m, std::uint8_t node, Frame& out) {
  if (!valid_node(node)) return false;
  Frame f = detail::start(Type::hil_tick_cost, node);
  detail::put_u16(&f.data[0], m.tick);
  detail::put_u32(&f.data[2], m.instructions);
  out = f;
  return true;
}

// ---------------------------------------------------------------------------------------
// Decoding: every path is a fixed sequence of checks, so a malformed frame costs no more
// than a good one. `out` is written only on success.
// ---------------------------------------------------------------------------------------
inline DecodeStatus decode(const Frame& f, Message& out) {
  using namespace detail;
  if (f.id > 0x7FFu) return DecodeStatus::unknown_type;
  const TypeInfo* info = find_type(id_type(f.id));
  if (info == nullptr) return DecodeStatus::unknown_type;
  if (f.len != info->length) return DecodeStatus::wrong_length;

  // Every byte defined: `out = m` copies the whole union, whichever member the frame set (GCC 12
  // at -O3 warns that the copy reads bytes a smaller member left unwritten).
  Message m;
  std::memset(static_cast<void*>(&m), 0, sizeof m);
  m.type = info->type;
  m.node = id_node(f.id);
  const std::uint8_t* d = f.data.data();
  switch (info->type) {
    case Type::kill:
      if (d[2] > kKillReasonMax) return DecodeStatus::out_of_range;
      m.kill = Kill{get_u16(d), static_cast<KillReason>(d[2])};
      break;
    case Type::command:
      if (d[0] == 0 || d[0] > kCommandCodeMax) return DecodeStatus::out_of_range;
      m.command = Command{static_cast<CommandCode>(d[0]), d[1], get_u16(d + 2),
                          static_cast<std::int32_t>(get_u32(d + 4))};
      break;
    case Type::rate_thrust: {
      RateThrust r{};
      for (int i = 0; i < 3; ++i) {
        if (get_u16(d + 2 * i) == 0x8000u) return DecodeStatus::out_of_range;  // -32768 is never sent
        r.rate_radps[i] = get_scaled_i16(d + 2 * i, kRateSetpointLsb_radps);
      }
      const std::uint16_t w = get_u16(d + 6);
      r.thrust_mps2 = static_cast<float>(w & 0x0FFFu) * kThrustLsb_mps2;
      r.seq = static_cast<std::uint8_t>(w >> 12);
      m.rate_thrust = r;
      break;
    }
    case Type::hil_imu_gyro:
    case Type::hil_imu_accel: {
      const float lsb = info->type == Type::hil_imu_gyro ? kGyroLsb_radps : kAccelLsb_mps2;
      std::array<float, 3> v{};
      for (int i = 0; i < 3; ++i) {
        if (get_u16(d + 2 * i) == 0x8000u) return DecodeStatus::out_of_range;
        v[i] = get_scaled_i16(d + 2 * i, lsb);
      }
      if (info->type == Type::hil_imu_gyro) m.hil_imu_gyro = HilImuGyro{v, get_u16(d + 6)};
      else m.hil_imu_accel = HilImuAccel{v, get_u16(d + 6)};
      break;
    }
    case Type::hil_motors: {
      std::uint64_t bits = 0;
      for (int i = 0; i < 6; ++i) bits |= static_cast<std::uint64_t>(d[i]) << (8 * i);
      HilMotors h{};
      for (int i = 0; i < 4; ++i)
        h.command[i] = static_cast<float>((bits >> (12 * i)) & 0xFFFu) / static_cast<float>(kMotorMax12);
      h.tick = get_u16(d + 6);
      m.hil_motors = h;
      break;
    }
    case Type::auth:
      m.auth = Auth{get_u16(d), static_cast<std::uint64_t>(get_u32(d + 2)) |
                                    (static_cast<std::uint64_t>(get_u16(d + 6)) << 32)};
      break;
    case Type::link_session: m.link_session = LinkSession{get_u32(d), get_u32(d + 4)}; break;
    case Type::impact: {
      const std::uint8_t cls = d[6] & static_cast<std::uint8_t>(~kImpactFinalBit);
      if (cls < kImpactClassMin || cls > kImpactClassMax) return DecodeStatus::out_of_range;
      m.impact = Impact{get_u32(d), static_cast<float>(get_u16(d + 4)) * kImpactPeakLsb_mps2,
                        static_cast<ImpactClass>(cls), (d[6] & kImpactFinalBit) != 0, d[7]};
      break;
    }
    case Type::command_ack:
      if (d[1] == 0 || d[1] > kCommandCodeMax || d[2] > kAckResultMax || d[3] > kModeMax ||
          d[4] > kRefuseReasonMax)
        return DecodeStatus::out_of_range;
      m.command_ack = CommandAck{d[0], static_cast<CommandCode>(d[1]), static_cast<AckResult>(d[2]),
                                 static_cast<Mode>(d[3]), static_cast<RefuseReason>(d[4])};
      break;
    case Type::gs_heartbeat:
      if (d[6] > kGroundStateMax) return DecodeStatus::out_of_range;
      m.gs_heartbeat = GsHeartbeat{get_u32(d), get_u16(d + 4), static_cast<GroundState>(d[6]), d[7]};
      break;
    case Type::vehicle_heartbeat:
      if (d[4] > kModeMax || (d[5] & ~kVehicleFlagsMask) != 0 || (d[6] >> 4) > kFailsafeReasonMax)
        return DecodeStatus::out_of_range;
      m.vehicle_heartbeat = VehicleHeartbeat{get_u32(d),
                                             static_cast<Mode>(d[4]),
                                             d[5],
                                             static_cast<std::uint8_t>(d[6] & 0x0Fu),
                                             static_cast<FailsafeReason>(d[6] >> 4),
                                             d[7]};
      break;
    case Type::timesync_request: m.timesync_request = TimesyncRequest{get_u32(d), d[4]}; break;
    case Type::timesync_reply: m.timesync_reply = TimesyncReply{get_u32(d), get_u32(d + 4)}; break;
    case Type::telemetry_rates: {
      TelemetryRates r{};
      for (int i = 0; i < 3; ++i) {
        if (get_u16(d + 2 * i) == 0x8000u) return DecodeStatus::out_of_range;
        r.rate_radps[i] = get_scaled_i16(d + 2 * i, kRateSetpointLsb_radps);
      }
      const std::uint16_t w = get_u16(d + 6);
      r.thrust_mps2 = static_cast<float>(w & 0x0FFFu) * kThrustLsb_mps2;
      r.saturation = static_cast<std::uint8_t>(w >> 12);
      m.telemetry_rates = r;
      break;
    }
    case Type::telemetry_attitude: {
      TelemetryAttitude a{};
      for (int i = 0; i < 4; ++i) {
        if (get_u16(d + 2 * i) == 0x8000u) return DecodeStatus::out_of_range;
        a.quaternion[i] = get_scaled_i16(d + 2 * i, kQuaternionLsb);
      }
      m.telemetry_attitude = a;
      break;
    }
    case Type::telemetry_motors: {
      TelemetryMotors t{};
      for (int i = 0; i < 4; ++i) t.command[i] = static_cast<float>(get_u16(d + 2 * i)) / kMotorMax16;
      m.telemetry_motors = t;
      break;
    }
    case Type::telemetry_status:
      m.telemetry_status = TelemetryStatus{get_u16(d), get_u16(d + 2), get_u16(d + 4), d[6], d[7]};
      break;
    case Type::hil_clock: m.hil_clock = HilClock{get_u32(d), get_u32(d + 4)}; break;
    case Type::hil_clock_done: m.hil_clock_done = HilClockDone{get_u32(d)}; break;
    case Type::hil_battery: m.hil_battery = HilBattery{get_u16(d)}; break;
    case Type::hil_tick_cost: m.hil_tick_cost = HilTickCost{get_u16(d), get_u32(d + 2)}; break;
  }
  out = m;
  return DecodeStatus::ok;
}

// Counters of rejected frames, kept by every receiver; saturating so they never wrap to zero.
struct RxCounters {
  std::uint32_t accepted = 0;
  std::uint32_t unknown_type = 0;
  std::uint32_t wrong_length = 0;
  std::uint32_t out_of_range = 0;
  std::uint32_t stale_sequence = 0;
  std::uint32_t wrong_direction = 0;  // a frame this side never receives (e.g. its own kind)
  std::uint32_t foreign_session = 0;  // a ground station other than the bound session
  std::uint32_t queue_full = 0;       // valid, but no room to keep it (the sender retries)
  std::uint32_t forged = 0;           // AUTH tag wrong, or a frame without its AUTH
  std::uint32_t replayed = 0;         // AUTH counter not above the last accepted one

  std::uint32_t rejected() const {
    return unknown_type + wrong_length + out_of_range + stale_sequence + wrong_direction + foreign_session +
           queue_full + forged + replayed;
  }
  void count(DecodeStatus s) {
    switch (s) {
      case DecodeStatus::ok: bump(accepted); break;
      case DecodeStatus::unknown_type: bump(unknown_type); break;
      case DecodeStatus::wrong_length: bump(wrong_length); break;
      case DecodeStatus::out_of_range: bump(out_of_range); break;
    }
  }
  static void bump(std::uint32_t& c) {
    if (c != 0xFFFFFFFFu) ++c;
  }
};

}  // namespace pa::proto
