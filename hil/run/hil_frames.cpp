#include "hil/run/hil_frames.hpp"

#include <algorithm>
#include <cmath>

namespace hil::run {

using pa::proto::Frame;
using pa::proto::Type;

std::uint16_t hil_tick(const ImuSample& sample) { return static_cast<std::uint16_t>(sample.tick & 0xFFFFu); }

std::array<Frame, 2> hil_imu_frames(const ImuSample& sample, std::uint8_t node) {
  const std::uint16_t tick = hil_tick(sample);
  const pa::proto::HilImuGyro gyro{
      {static_cast<float>(sample.gyro_radps.x()), static_cast<float>(sample.gyro_radps.y()),
       static_cast<float>(sample.gyro_radps.z())},
      tick};
  const pa::proto::HilImuAccel accel{
      {static_cast<float>(sample.accel_mps2.x()), static_cast<float>(sample.accel_mps2.y()),
       static_cast<float>(sample.accel_mps2.z())},
      tick};
  std::array<Frame, 2> frames{};
  pa::proto::encode(gyro, node, frames[0]);
  pa::proto::encode(accel, node, frames[1]);
  return frames;
}

std::optional<Frame> hil_battery_frame(const Plant& plant, pa::VehicleId vehicle, const ImuSample& sample) {
  if (sample.tick % kHilBatteryPeriod_ticks != 0) return std::nullopt;
  const BatteryConfig& battery = plant.config().battery;
  const double voltage_V =
      battery.enabled != 0 ? plant.battery(vehicle).voltage_V : battery.reference_voltage_V;
  const double mv = std::round(voltage_V * 1000.0);
  const pa::proto::HilBattery message{
      static_cast<std::uint16_t>(std::isfinite(mv) ? std::clamp(mv, 0.0, 65535.0) : 0.0)};
  Frame f;
  if (!pa::proto::encode(message, vehicle.node(), f)) return std::nullopt;
  return f;
}

MotorsAnswer read_hil_motors(const Frame& frame, std::uint8_t node, std::uint16_t tick, MotorCommands& out) {
  if (pa::proto::id_type(frame.id) != static_cast<std::uint8_t>(Type::hil_motors))
    return MotorsAnswer::not_motors;
  pa::proto::Message m;
  if (pa::proto::decode(frame, m) != pa::proto::DecodeStatus::ok || m.type != Type::hil_motors ||
      m.node != node)
    return MotorsAnswer::not_motors;
  if (m.hil_motors.tick != tick) return MotorsAnswer::other_tick;
  for (int k = 0; k < 4; ++k) out.command[k] = static_cast<double>(m.hil_motors.command[k]);
  return MotorsAnswer::answer;
}

bool radio_carries(const Frame& frame) {
  const pa::proto::TypeInfo* info = pa::proto::find_type(pa::proto::id_type(frame.id));
  if (info == nullptr) return true;  // a radio carries bytes, not meaning: the receiver rejects it
  return info->direction == pa::proto::Direction::ground_to_vehicle ||
         info->direction == pa::proto::Direction::vehicle_to_ground;
}

}  // namespace hil::run
