// The seam between the firmware core and a board: both STM32F405 images run this one step,
// an IMU sample in, Vehicle::tick measured on the DWT cycle counter, the motor command out,
// then the frames the core has to send. Where the sample comes from and where the commands
// and frames go is the image's `Io`:
//   void write_motors(const fw::TickOutput& out);  // HIL: a HIL_MOTORS frame; flight: DShot
//   void send(const pa::proto::Frame& frame);      // HIL: CAN1; flight: the UART radio link
// No heap; the step is bounded by Vehicle::tick and the core's transmit queue.
#pragma once

#include <cstdint>

#include "cycle_counter.hpp"
#include "fw/vehicle.hpp"
#include "pa/protocol.hpp"

namespace stm32f405 {

struct TickStats {
  std::uint32_t ticks = 0;             // samples that ran a tick
  std::uint32_t tick_cycles_last = 0;  // DWT cycles of Vehicle::tick
  std::uint32_t tick_cycles_max = 0;
};

template <class Io>
class VehicleNode {
 public:
  // `cycles_per_us`: the CPU clock in MHz, to report tick times in microseconds.
  VehicleNode(const fw::VehicleConfig& config, std::uint32_t cycles_per_us, Io io)
      : vehicle_(config), io_(io), cycles_per_us_(cycles_per_us == 0 ? 1 : cycles_per_us) {}

  // A frame for the core, on the clock of the IMU samples.
  void on_frame(const pa::proto::Frame& frame, std::uint32_t now_us) { vehicle_.on_frame(frame, now_us); }

  void on_imu_sample(const fw::ImuSample& sample) {
    const std::uint32_t start = CycleCounter::now();
    const fw::TickOutput out = vehicle_.tick(sample);
    const std::uint32_t cycles = CycleCounter::now() - start;
    vehicle_.note_tick_time_us((cycles + cycles_per_us_ - 1u) / cycles_per_us_);
    ++stats_.ticks;
    stats_.tick_cycles_last = cycles;
    if (cycles > stats_.tick_cycles_max) stats_.tick_cycles_max = cycles;

    io_.write_motors(out);
    pa::proto::Frame frame;
    while (vehicle_.pop_tx(frame)) io_.send(frame);
  }

  fw::Vehicle& vehicle() { return vehicle_; }
  const fw::Vehicle& vehicle() const { return vehicle_; }
  const TickStats& stats() const { return stats_; }
  Io& io() { return io_; }

 private:
  fw::Vehicle vehicle_;
  Io io_;
  std::uint32_t cycles_per_us_;
  TickStats stats_{};
};

}  // namespace stm32f405
