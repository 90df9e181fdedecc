// What the trials read of a vehicle's firmware (its mode, why it failed safe, the impacts it
// counted, the setpoint it flies), the same for the core in process and for the flight image in
// QEMU (emulated_firmware.hpp), which has no fw::Vehicle in this process to read.
#pragma once

#include <cstdint>

#include "pa/protocol.hpp"

namespace hil::sil {

struct FirmwareObservation {
  pa::proto::Mode mode = pa::proto::Mode::disarmed;
  pa::proto::FailsafeReason failsafe_reason = pa::proto::FailsafeReason::none;
  std::uint8_t impact_count = 0;
  // The latest setpoint (zero thrust and rates before the first).
  pa::proto::RateThrust setpoint{};
};

// The setpoint age that means "none received yet" (fw::CommandLink::setpoint_age_us()).
inline constexpr std::uint32_t kNoSetpoint = 0xFFFFFFFFu;

}  // namespace hil::sil
