// Hardware-in-the-loop IMU: the plant sends each 1 kHz sample as two frames (HIL_IMU_GYRO and
// HIL_IMU_ACCEL, both carrying the tick number); the sample is complete when both halves of
// the same tick are in. A half from an older tick is dropped, so a lost frame costs one
// sample, never a mixed one.
#pragma once

#include <cstdint>

#include "fw/types.hpp"
#include "pa/constants.hpp"
#include "pa/protocol.hpp"

namespace fw {

class HilImuAssembler {
 public:
  // Returns true when `out` holds a complete sample (time = tick * 1 ms on the plant's clock,
  // unwrapped from the 16-bit tick).
  bool on_message(const pa::proto::Message& m, ImuSample& out) {
    using pa::proto::Type;
    if (m.type == Type::hil_imu_gyro) {
      start(m.hil_imu_gyro.tick);
      sample_.gyro_radps = m.hil_imu_gyro.gyro_radps;
      have_gyro_ = true;
    } else if (m.type == Type::hil_imu_accel) {
      start(m.hil_imu_accel.tick);
      sample_.accel_mps2 = m.hil_imu_accel.accel_mps2;
      have_accel_ = true;
    } else {
      return false;
    }
    if (!(have_gyro_ && have_accel_)) return false;
    have_gyro_ = have_accel_ = false;
    sample_.t_us = ticks_ * pa::kImuPeriod_us;
    out = sample_;
    return true;
  }
  std::uint16_t tick() const { return tick_; }

 private:
  void start(std::uint16_t tick) {
    if (tick == tick_ && started_) return;
    // Unwrap the 16-bit tick into a 32-bit count so the microsecond clock keeps running.
    ticks_ += started_ ? static_cast<std::uint16_t>(tick - tick_) : tick;
    tick_ = tick;
    started_ = true;
    have_gyro_ = have_accel_ = false;
  }

  ImuSample sample_{};
  std::uint16_t tick_ = 0;
  std::uint32_t ticks_ = 0;
  bool started_ = false;
  bool have_gyro_ = false;
  bool have_accel_ = false;
};

}  // namespace fw
