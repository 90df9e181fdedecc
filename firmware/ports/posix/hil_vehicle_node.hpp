// One vehicle as the HIL sees it: frames from its vehicle bus in, frames out. HIL_IMU frames
// from the plant are assembled into samples that run the 1 kHz tick (the vehicle's clock is
// the plant's tick clock, so a run is reproducible); the motor outputs go back as HIL_MOTORS
// with the same tick, followed by whatever the firmware has to send. Shared by the SocketCAN
// process and the in-memory simulation. No heap.
#pragma once

#include <cstdint>

#include "fw/hil_imu.hpp"
#include "fw/vehicle.hpp"

namespace fw::posix {

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
    vehicle_.note_tick_time_us(static_cast<std::uint32_t>((monotonic_ns() - start_ns) / 1000u));

    pa::proto::Frame reply;
    const pa::proto::HilMotors motors{out.motors_enabled ? out.motor_command : Motors{}, imu_.tick()};
    if (pa::proto::encode(motors, node_, reply)) send(reply);
    while (vehicle_.pop_tx(reply)) send(reply);
  }

  const Vehicle& vehicle() const { return vehicle_; }

 private:
  static std::uint64_t monotonic_ns();

  Vehicle vehicle_;
  HilImuAssembler imu_{};
  std::uint8_t node_;
  std::uint32_t now_us_ = 0;
};

}  // namespace fw::posix
