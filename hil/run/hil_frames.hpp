// The HIL exchange on a vehicle bus as the plant speaks it (docs/protocol.md): a plant IMU sample
// as HIL_IMU_GYRO and HIL_IMU_ACCEL frames, its battery's voltage as HIL_BATTERY, the firmware's
// HIL_MOTORS answer read back into the
// commands the plant holds, and which frames a radio carries. Shared by the in-process firmware
// (firmware_vehicle.hpp) and `hil run`, which speaks it to fw_vehicle processes over SocketCAN,
// so that both quantise and match the samples the same way.
#pragma once

#include <array>
#include <cstdint>
#include <optional>

#include "hil/plant/imu.hpp"
#include "hil/plant/plant.hpp"
#include "hil/plant/types.hpp"
#include "pa/protocol.hpp"

namespace hil::run {

// The HIL_IMU tick of a plant sample: its count modulo 2^16 (the firmware unwraps it).
std::uint16_t hil_tick(const ImuSample& sample);

// The sample as the two frames to vehicle `node`, gyro first (the firmware runs its tick when
// both of a tick have arrived).
std::array<pa::proto::Frame, 2> hil_imu_frames(const ImuSample& sample, std::uint8_t node);

// The plant's battery as the firmware's HIL ports read it: with every kHilBatteryPeriod_ticks-th
// sample (its tick a multiple of it, 100 Hz, the rate a flight image polls its VBAT ADC) a
// HIL_BATTERY frame to `vehicle` carrying the pack's terminal voltage under load as of the step
// that made `sample` (Plant::battery()), rounded to the millivolt; it goes on the bus before the
// sample's IMU frames, so that tick already flies on it. With battery_enabled 0 the plant's
// motors make the thrust of the reference voltage, so that is the voltage sent (the firmware's
// compensation factor is then exactly 1). std::nullopt on the other ticks.
inline constexpr std::uint64_t kHilBatteryPeriod_ticks = 10;
std::optional<pa::proto::Frame> hil_battery_frame(const Plant& plant, pa::VehicleId vehicle,
                                                  const ImuSample& sample);

enum class MotorsAnswer {
  not_motors,  // any other frame, or another node's HIL_MOTORS
  other_tick,  // node's HIL_MOTORS, but for another sample (a late answer)
  answer,      // node's HIL_MOTORS for `tick`: its commands are in `out`
};
// Reads `frame` as vehicle `node`'s answer to sample `tick`; `out` changes only on an answer.
// Units: both sides use the normalised thrust fraction (firmware_config_for()), so the mapping is
// one to one; the plant clamps to 0..1 itself.
MotorsAnswer read_hil_motors(const pa::proto::Frame& frame, std::uint8_t node, std::uint16_t tick,
                             MotorCommands& out);

// Whether a radio between a vehicle bus and the ground bus carries the frame: everything but the
// HIL frames, which exist only between the plant and its firmware or its ground station.
bool radio_carries(const pa::proto::Frame& frame);

}  // namespace hil::run
