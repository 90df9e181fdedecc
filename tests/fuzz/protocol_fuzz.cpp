// Fuzzes pa::proto::decode with arbitrary identifiers and 0..8-byte frames.
// Input: id (2 bytes, little-endian, any 16-bit value), then the payload; its length (beyond 8
// bytes, truncated) is the frame's data length code.
//
// Invariants (protocol.hpp): decode never reads past the frame and writes `out` only on
// success; an accepted frame has its catalogue length and a valid 11-bit id; it re-encodes to
// the same id and payload bytes. The last holds by design: decode rejects every value encode
// cannot produce (reserved bits, -32768 in scaled fields, out-of-range enumerations), and every
// scaled field decodes to count * lsb, which encode quantises back to the same count.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "pa/protocol.hpp"

namespace {

using namespace pa::proto;

bool re_encode(const Message& m, Frame& out) {
  switch (m.type) {
    case Type::kill: return encode(m.kill, m.node, out);
    case Type::command: return encode(m.command, m.node, out);
    case Type::rate_thrust: return encode(m.rate_thrust, m.node, out);
    case Type::hil_imu_gyro: return encode(m.hil_imu_gyro, m.node, out);
    case Type::hil_imu_accel: return encode(m.hil_imu_accel, m.node, out);
    case Type::hil_motors: return encode(m.hil_motors, m.node, out);
    case Type::auth: return encode(m.auth, m.node, out);
    case Type::link_session: return encode(m.link_session, m.node, out);
    case Type::impact: return encode(m.impact, m.node, out);
    case Type::command_ack: return encode(m.command_ack, m.node, out);
    case Type::gs_heartbeat: return encode(m.gs_heartbeat, m.node, out);
    case Type::vehicle_heartbeat: return encode(m.vehicle_heartbeat, m.node, out);
    case Type::timesync_request: return encode(m.timesync_request, m.node, out);
    case Type::timesync_reply: return encode(m.timesync_reply, m.node, out);
    case Type::telemetry_rates: return encode(m.telemetry_rates, m.node, out);
    case Type::telemetry_attitude: return encode(m.telemetry_attitude, m.node, out);
    case Type::telemetry_motors: return encode(m.telemetry_motors, m.node, out);
    case Type::telemetry_status: return encode(m.telemetry_status, m.node, out);
    case Type::hil_clock: return encode(m.hil_clock, m.node, out);
    case Type::hil_clock_done: return encode(m.hil_clock_done, m.node, out);
    case Type::hil_battery: return encode(m.hil_battery, m.node, out);
    case Type::hil_tick_cost: return encode(m.hil_tick_cost, m.node, out);
  }
  return false;
}

void check(bool condition) {
  if (!condition) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  Frame f;
  f.id = static_cast<std::uint16_t>(data[0] | (data[1] << 8));
  const std::size_t len = size - 2 > kMaxPayload ? kMaxPayload : size - 2;
  f.len = static_cast<std::uint8_t>(len);
  std::memcpy(f.data.data(), data + 2, len);

  // A sentinel: decode must leave `out` alone on failure.
  Message m;
  m.type = Type::telemetry_status;
  m.node = 0xEE;
  const DecodeStatus status = decode(f, m);
  if (status != DecodeStatus::ok) {
    check(m.type == Type::telemetry_status && m.node == 0xEE);
    return 0;
  }

  const TypeInfo* info = find_type(static_cast<std::uint8_t>(m.type));
  check(info != nullptr && info->type == m.type && info->length == f.len);
  check(f.id <= 0x7FFu && make_id(m.type, m.node) == f.id);

  Frame again;
  check(re_encode(m, again));
  check(again.id == f.id && again.len == f.len);
  check(std::memcmp(again.data.data(), f.data.data(), f.len) == 0);

  // A second decode of the re-encoded frame gives the same message (idempotence).
  Message m2;
  check(decode(again, m2) == DecodeStatus::ok && m2.type == m.type && m2.node == m.node);
  return 0;
}
