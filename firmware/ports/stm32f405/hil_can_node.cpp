#include "hil_can_node.hpp"

#include "bxcan.hpp"
#include "cycle_counter.hpp"

namespace stm32f405 {

using namespace pa::proto;

HilCanNode::HilCanNode(const fw::VehicleConfig& config, std::uint32_t cycles_per_us)
    : vehicle_(config),
      node_(config.link.vehicle.node()),
      cycles_per_us_(cycles_per_us == 0 ? 1 : cycles_per_us) {}

void HilCanNode::send(const Frame& frame) {
  if (!Can1::send(frame)) ++stats_.tx_dropped;
}

void HilCanNode::on_frame(const Frame& frame) {
  Message m;
  const DecodeStatus status = decode(frame, m);
  const bool hil_imu =
      status == DecodeStatus::ok && (m.type == Type::hil_imu_gyro || m.type == Type::hil_imu_accel);
  if (!hil_imu) {
    vehicle_.on_frame(frame, now_us_);  // the core counts what it cannot use
    return;
  }
  if (m.node != node_) {
    ++stats_.other_node_samples;
    return;
  }
  fw::ImuSample sample;
  if (!imu_.on_message(m, sample)) return;
  now_us_ = sample.t_us;

  const std::uint32_t start = CycleCounter::now();
  const fw::TickOutput out = vehicle_.tick(sample);
  const std::uint32_t cycles = CycleCounter::now() - start;
  vehicle_.note_tick_time_us((cycles + cycles_per_us_ - 1u) / cycles_per_us_);
  ++stats_.ticks;
  stats_.tick_cycles_last = cycles;
  if (cycles > stats_.tick_cycles_max) stats_.tick_cycles_max = cycles;

  Frame reply;
  const HilMotors motors{out.motors_enabled ? out.motor_command : fw::Motors{}, imu_.tick()};
  if (encode(motors, node_, reply)) send(reply);
  while (vehicle_.pop_tx(reply)) send(reply);
}

}  // namespace stm32f405
