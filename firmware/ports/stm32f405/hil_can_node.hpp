// The vehicle in hardware-in-the-loop mode over CAN: the plant on the vehicle bus sends each
// 1 kHz IMU sample as HIL_IMU_GYRO + HIL_IMU_ACCEL; the complete sample runs Vehicle::tick
// (through VehicleNode, the step the flight image shares), whose motor outputs go back as
// HIL_MOTORS with the same tick, followed by whatever the core has to send. As in the POSIX
// port (firmware/ports/posix/hil_vehicle_node.hpp) the vehicle's clock is the plant's tick
// clock, so a HIL run on the board matches one on the host. Every other frame goes to the
// core, which validates and counts it. No heap.
#pragma once

#include <cstdint>

#include "fw/hil_imu.hpp"
#include "fw/vehicle.hpp"
#include "pa/protocol.hpp"
#include "vehicle_node.hpp"

namespace stm32f405 {

struct HilCanStats {
  std::uint32_t ticks = 0;             // complete samples that ran a tick
  std::uint32_t tick_cycles_last = 0;  // DWT cycles of Vehicle::tick
  std::uint32_t tick_cycles_max = 0;
  std::uint32_t other_node_samples = 0;  // HIL IMU frames for another vehicle, ignored
  std::uint32_t tx_dropped = 0;          // frames the CAN queue refused
};

class HilCanNode {
 public:
  // `cycles_per_us`: the CPU clock in MHz, to report tick times in microseconds.
  HilCanNode(const fw::VehicleConfig& config, std::uint32_t cycles_per_us);

  void on_frame(const pa::proto::Frame& frame);

  const fw::Vehicle& vehicle() const { return node_.vehicle(); }
  const HilCanStats& stats() const { return stats_; }

 private:
  // The HIL image's side of the seam: motors and frames go onto CAN1.
  struct Io {
    HilCanNode* self;
    void write_motors(const fw::TickOutput& out);
    void send(const pa::proto::Frame& frame);
  };

  VehicleNode<Io> node_;
  fw::HilImuAssembler imu_{};
  std::uint8_t node_id_;
  std::uint32_t now_us_ = 0;  // the plant's clock: the time of the last complete sample
  HilCanStats stats_{};
};

}  // namespace stm32f405
