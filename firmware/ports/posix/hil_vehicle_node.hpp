// One vehicle as the HIL sees it: frames from its vehicle bus in, frames out. HIL_IMU frames
// from the plant are assembled into samples that run the 1 kHz tick (the vehicle's clock is
// the plant's tick clock, so a run is reproducible); the motor outputs go back as HIL_MOTORS
// with the same tick, followed by whatever the firmware has to send; HIL_BATTERY is the pack's
// voltage, the reading a flight image takes from its ADC. Shared by the SocketCAN
// process, the in-memory simulation and the mps2-an386 processor-in-the-loop image
// (firmware/ports/mps2_an386/pil_main.cpp, which includes this header and defines its own
// monotonic_ns()). No heap.
#pragma once

#include <array>
#include <cstdint>

#include "fw/hil_imu.hpp"
#include "fw/vehicle.hpp"

namespace fw::posix {

// A change of the supervisor's mode, for the process's log: when (the vehicle's clock), why, and
// how old the ground's last setpoint was then (the failsafe's 20 ms, seen from outside).
struct ModeChange {
  std::uint32_t t_us = 0;
  pa::proto::Mode from = pa::proto::Mode::disarmed;
  pa::proto::Mode to = pa::proto::Mode::disarmed;
  pa::proto::FailsafeReason reason = pa::proto::FailsafeReason::none;
  std::uint32_t setpoint_age_us = 0;
};

class HilVehicleNode {
 public:
  explicit HilVehicleNode(const VehicleConfig& config)
      : vehicle_(config), node_(config.link.vehicle.node()) {}

  // `send(const Frame&)` is called for every frame the vehicle answers with.
  template <class Send>
  void on_frame(const pa::proto::Frame& frame, Send&& send) {
    pa::proto::Message m;
    const pa::proto::DecodeStatus status = pa::proto::decode(frame, m);
    const bool hil_imu = status == pa::proto::DecodeStatus::ok && (m.type == pa::proto::Type::hil_imu_gyro ||
                                                                   m.type == pa::proto::Type::hil_imu_accel);
    if (status == pa::proto::DecodeStatus::ok && m.type == pa::proto::Type::hil_battery) {
      if (m.node == node_) vehicle_.note_battery_mv(m.hil_battery.voltage_mv);  // the plant's pack
      return;
    }
    if (!hil_imu) {
      vehicle_.on_frame(frame, now_us_);  // the core counts what it cannot use
      return;
    }
    if (m.node != node_) return;
    ImuSample sample;
    if (!imu_.on_message(m, sample)) return;
    now_us_ = sample.t_us;
    const std::uint64_t start_ns = monotonic_ns();
    const TickOutput out = vehicle_.tick(sample);
    last_tick_ns_ = monotonic_ns() - start_ns;
    vehicle_.note_tick_time_us(static_cast<std::uint32_t>(last_tick_ns_ / 1000u));
    if (vehicle_.mode() != mode_) {
      changes_[change_count_ % kChanges] =
          ModeChange{now_us_, mode_, vehicle_.mode(), vehicle_.failsafe_reason(),
                     vehicle_.link().setpoint_age_us(now_us_)};
      ++change_count_;
      mode_ = vehicle_.mode();
    }

    pa::proto::Frame reply;
    const pa::proto::HilMotors motors{out.motors_enabled ? out.motor_command : Motors{}, imu_.tick()};
    if (pa::proto::encode(motors, node_, reply)) send(reply);
    while (vehicle_.pop_tx(reply)) send(reply);
  }

  const Vehicle& vehicle() const { return vehicle_; }
  // How long the last Vehicle::tick took on monotonic_ns()'s clock, the readings' own cost
  // included (0 before the first tick).
  std::uint64_t last_tick_ns() const { return last_tick_ns_; }
  // The oldest mode change not taken yet; the ring keeps the latest kChanges.
  bool take_mode_change(ModeChange& out) {
    if (change_count_ - changes_taken_ > kChanges) changes_taken_ = change_count_ - kChanges;
    if (changes_taken_ == change_count_) return false;
    out = changes_[changes_taken_++ % kChanges];
    return true;
  }

  // The port's clock, which times each tick (defined once per port: CLOCK_MONOTONIC on Linux,
  // the instruction counter's virtual nanoseconds on the mps2-an386 PIL image). Public so a port
  // can measure what a reading costs.
  static std::uint64_t monotonic_ns();

 private:
  Vehicle vehicle_;
  HilImuAssembler imu_{};
  std::uint8_t node_;
  std::uint32_t now_us_ = 0;
  std::uint64_t last_tick_ns_ = 0;
  static constexpr std::uint32_t kChanges = 8;
  std::array<ModeChange, kChanges> changes_{};
  std::uint32_t change_count_ = 0;
  std::uint32_t changes_taken_ = 0;
  pa::proto::Mode mode_ = pa::proto::Mode::disarmed;
};

}  // namespace fw::posix
