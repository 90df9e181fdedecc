// Fuzzes the firmware's frame handling: fw::Vehicle (node 1) fed an arbitrary sequence of
// received frames and IMU ticks, with the supervisor's safety invariants checked after every
// step (a violation traps, which libFuzzer reports as a crash).
//
// Input: 12-byte records (a shorter tail is ignored).
//   frame: [op, op & 0x80 == 0] [id lo] [id hi] [len] [data 0..7]  (len > 8 is clamped to 8);
//          op bit 0x40: the harness, holding the vehicle's key, sends the frame's AUTH after it
//          (a ground station's frame); without it the frame comes alone (anyone's)
//   tick:  [op, op & 0x80 != 0] [dt] [gx gy gz ax ay az as int8] [pad x 4]
//          the clock advances dt * 250 us; gyro = int8 * 0.02 rad/s, accel = int8 * 0.2 m/s^2
//          with +9.81 on z; op bit 0x40 makes gyro x NaN, bit 0x20 makes accel z 1e6
//          (unhealthy samples).
// Fixed-size records keep a mutation inside one record from shifting every later one.
//
// Invariants:
// - frames never change the mode: only tick() acts on them;
// - the motors never start (a motors-off mode to a motors-on one) without a signed ARM command
//   for this node received since they last started and its accepted COMMAND_ACK sent in that
//   tick: nobody without the key starts them;
// - KILL is always honoured: after a signed KILL for this node that found the link's queue
//   empty, the next tick's motors are off, and the vehicle is killed (or disarmed, when a
//   DISARM followed it);
// - the motor commands are finite, within 0..1, and all zero when the motors are off, whatever
//   HIL_BATTERY voltages arrived (the battery's factor stays within its limits).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "fw/vehicle.hpp"

namespace {

using namespace pa::proto;

constexpr std::size_t kRecord = 12;
constexpr std::uint8_t kNode = 1;
constexpr pa::auth::Key kKey{0xF0, 0x22, 0x10, 0x01, 0x5A, 0xA5, 0x3C, 0xC3,
                             0x96, 0x69, 0x0F, 0xF0, 0x11, 0x22, 0x33, 0x44};
constexpr std::uint32_t kNonce = 0xF022;

void check(bool condition) {
  if (!condition) __builtin_trap();
}

bool motors_on(Mode mode) { return fw::action_for(mode) != fw::Action::motors_off; }

// What signed frames arrived for this vehicle: a KILL since the last tick (that will be verified
// in the next one), an ARM since the motors last started.
struct Received {
  bool kill = false;
  bool arm = false;
};

void note_signed_frame(const Frame& f, bool queue_empty, Received& received) {
  Message m;
  if (decode(f, m) != DecodeStatus::ok || m.node != kNode) return;
  if (m.type == Type::kill && queue_empty) received.kill = true;
  if (m.type == Type::command && m.command.code == CommandCode::arm) received.arm = true;
}

// Drains the transmit queue; true when an accepted ARM acknowledgement was among the frames.
bool drain_tx(fw::Vehicle& vehicle) {
  bool arm_accepted = false;
  Frame f;
  while (vehicle.pop_tx(f)) {
    Message m;
    // Whatever the vehicle sends must decode: encode() and decode() agree.
    check(decode(f, m) == DecodeStatus::ok);
    check(m.node == kNode);
    if (m.type == Type::command_ack && m.command_ack.code == CommandCode::arm &&
        m.command_ack.result == AckResult::accepted)
      arm_accepted = true;
  }
  return arm_accepted;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fw::VehicleConfig config{};
  config.link.vehicle = pa::VehicleId(kNode);
  config.link.key = kKey;
  config.link.session_nonce = kNonce;
  fw::Vehicle vehicle(config);  // a fresh vehicle per input: each input is one boot
  pa::auth::Signer ground(kKey);
  ground.start_session(kNonce, 0);

  std::uint32_t now_us = 0;
  Received received;
  for (std::size_t at = 0; at + kRecord <= size; at += kRecord) {
    const std::uint8_t* r = data + at;
    const Mode before = vehicle.mode();
    if ((r[0] & 0x80u) == 0) {
      Frame f;
      f.id = static_cast<std::uint16_t>(r[1] | (r[2] << 8));
      f.len = r[3] > kMaxPayload ? kMaxPayload : r[3];
      std::memcpy(f.data.data(), r + 4, kMaxPayload);
      Frame auth;
      const bool signed_frame = (r[0] & 0x40u) != 0 && ground.sign(f, auth);
      if (signed_frame) note_signed_frame(f, vehicle.guard().queued() == 0, received);
      // A HIL port reads the battery's HIL_BATTERY from its bus into the vehicle (posix/
      // hil_vehicle_node.hpp); the core itself counts it and drops it like any HIL frame.
      Message battery;
      if (decode(f, battery) == DecodeStatus::ok && battery.type == Type::hil_battery &&
          battery.node == kNode)
        vehicle.note_battery_mv(battery.hil_battery.voltage_mv);
      vehicle.on_frame(f, now_us);
      if (signed_frame) vehicle.on_frame(auth, now_us);
      check(vehicle.mode() == before);
      continue;
    }

    now_us += static_cast<std::uint32_t>(r[1]) * 250u;
    fw::ImuSample s;
    s.t_us = now_us;
    for (int i = 0; i < 3; ++i) {
      s.gyro_radps[i] = static_cast<float>(static_cast<std::int8_t>(r[2 + i])) * 0.02f;
      s.accel_mps2[i] = static_cast<float>(static_cast<std::int8_t>(r[5 + i])) * 0.2f;
    }
    s.accel_mps2[2] += 9.81f;
    if (r[0] & 0x40u) s.gyro_radps[0] = std::nanf("");
    if (r[0] & 0x20u) s.accel_mps2[2] = 1e6f;

    const fw::TickOutput out = vehicle.tick(s);
    const Mode after = vehicle.mode();
    const bool arm_accepted = drain_tx(vehicle);

    if (!motors_on(before) && motors_on(after)) {
      check(received.arm && arm_accepted);
      received.arm = false;
    }
    if (received.kill) {
      check(!out.motors_enabled);
      check(after == Mode::killed || after == Mode::disarmed);
    }
    check(out.motors_enabled == motors_on(after));
    const float factor = vehicle.battery().factor();
    check(factor >= 1.0f / (fw::BatteryCompensation::kValidMax * fw::BatteryCompensation::kValidMax) &&
          factor <= fw::BatteryCompensation::kFactorMax);
    for (float m : out.motor_command) {
      check(std::isfinite(m) && m >= 0.0f && m <= 1.0f);
      if (!out.motors_enabled) check(m == 0.0f);
    }
    received.kill = false;
  }
  return 0;
}
