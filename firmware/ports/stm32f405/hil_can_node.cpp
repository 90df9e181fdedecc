#include "hil_can_node.hpp"

#include "bxcan.hpp"

namespace stm32f405 {

using namespace pa::proto;

HilCanNode::HilCanNode(const fw::VehicleConfig& config, std::uint32_t cycles_per_us)
    : node_(config, cycles_per_us, Io{this}), node_id_(config.link.vehicle.node()) {}

void HilCanNode::Io::send(const Frame& frame) {
  if (!Can1::send(frame)) ++self->stats_.tx_dropped;
}

void HilCanNode::Io::write_motors(const fw::TickOutput& out) {
  Frame reply;
  const HilMotors motors{out.motors_enabled ? out.motor_command : fw::Motors{}, self->imu_.tick()};
  if (encode(motors, self->node_id_, reply)) send(reply);
}

void HilCanNode::on_frame(const Frame& frame) {
  Message m;
  const DecodeStatus status = decode(frame, m);
  const bool hil_imu =
      status == DecodeStatus::ok && (m.type == Type::hil_imu_gyro || m.type == Type::hil_imu_accel);
  if (status == DecodeStatus::ok && m.type == Type::hil_battery) {
    // The plant's pack, which the flight image reads from its ADC instead.
    if (m.node == node_id_) node_.vehicle().note_battery_mv(m.hil_battery.voltage_mv);
    return;
  }
  if (!hil_imu) {
    node_.on_frame(frame, now_us_);  // the core counts what it cannot use
    return;
  }
  if (m.node != node_id_) {
    ++stats_.other_node_samples;
    return;
  }
  fw::ImuSample sample;
  if (!imu_.on_message(m, sample)) return;
  now_us_ = sample.t_us;

  node_.on_imu_sample(sample);
  const TickStats& t = node_.stats();
  stats_.ticks = t.ticks;
  stats_.tick_cycles_last = t.tick_cycles_last;
  stats_.tick_cycles_max = t.tick_cycles_max;
}

}  // namespace stm32f405
