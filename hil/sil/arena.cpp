#include "hil/sil/arena.hpp"

#include <stdexcept>
#include <string>

namespace hil::sil {

using pa::proto::Frame;

namespace {

// Times built from whole nanoseconds and sums of latencies land a rounding error off the
// millisecond grid; well below any period, this keeps a frame due on the grid on its step.
constexpr double kGridTolerance_s = 1e-9;

// splitmix64: nearby arena seeds and the two nodes give unrelated radio seeds.
std::uint64_t mix(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

}  // namespace

RadioConfig with_plant_losses(RadioConfig radio, const PlantConfig& plant) {
  radio.loss = plant.radio_loss_probability;
  radio.outage_s = plant.radio_outage_s;
  return radio;
}

RadioConfig arena_radio_config(RadioConfig radio, std::uint64_t arena_seed, pa::VehicleId vehicle) {
  // The top half: splitmix64's best-mixed bits.
  radio.seed = static_cast<std::uint32_t>(
      mix(mix(arena_seed) ^ ((0x100u + vehicle.node()) * 0xD1B54A32D192ED03ull)) >> 32);
  return radio;
}

std::array<bool, 2> radios_carrying(const Frame& frame) {
  const std::uint8_t node = pa::proto::id_node(frame.id);
  if (node == pa::proto::kBroadcastNode) return {true, true};
  std::array<bool, 2> carrying{false, false};
  if (pa::is_act_vehicle(pa::VehicleId(node))) carrying[pa::act_slot(pa::VehicleId(node))] = true;
  return carrying;
}

Arena::Arena(const PlantConfig& plant, const ArenaConfig& config, std::uint64_t seed)
    : lockstep_(plant, seed) {
  links_.reserve(2);
  for (const pa::VehicleId v : pa::kActVehicles) {
    links_.emplace_back(arena_radio_config(config.radio, seed, v));
    fw::VehicleConfig firmware = firmware_config_for(plant.vehicle, v, plant.battery.reference_voltage_V);
    firmware.link.session_nonce = static_cast<std::uint32_t>(mix(seed ^ (0x200u + v.node())) >> 32);
    vehicles_[pa::act_slot(v)] = &lockstep_.attach_firmware(firmware);
  }
}

Arena::Arena(const Arena& other)
    : lockstep_(other.lockstep_),
      links_(other.links_),
      ground_(other.ground_),
      mocap_(other.mocap_),
      not_carried_(other.not_carried_),
      uplink_silent_(other.uplink_silent_) {
  for (const pa::VehicleId v : pa::kActVehicles) vehicles_[pa::act_slot(v)] = lockstep_.firmware(v);
}

std::size_t Arena::slot(pa::VehicleId vehicle) {
  if (!pa::is_act_vehicle(vehicle))
    throw std::out_of_range("no arena vehicle has node " + std::to_string(vehicle.node()) + " (1 or 2)");
  return pa::act_slot(vehicle);
}

FirmwareVehicle& Arena::vehicle(pa::VehicleId vehicle) { return *vehicles_[slot(vehicle)]; }
const FirmwareVehicle& Arena::vehicle(pa::VehicleId vehicle) const { return *vehicles_[slot(vehicle)]; }

void Arena::send_from_ground(const Frame& frame) {
  const std::array<bool, 2> carrying = radios_carrying(frame);
  if (!carrying[0] && !carrying[1]) ++not_carried_;
  for (std::size_t v = 0; v < 2; ++v)
    if (carrying[v]) links_[v].bridge.offer(Side::ground, frame, t_s());
}

void Arena::step() {
  const double start = t_s() + kGridTolerance_s;
  Frame f;
  for (std::size_t v = 0; v < 2; ++v) {
    while (links_[v].bridge.deliver(Side::vehicle, start, f)) {
      if (uplink_silent_) continue;
      vehicles_[v]->inject(f);
      ++links_[v].uplink_delivered;
    }
  }
  lockstep_.step();
  const double t_end = t_s();
  const bool losses = lockstep_.plant().losses_active();
  for (Link& link : links_) link.bridge.set_losses_active(losses);
  for (std::size_t v = 0; v < 2; ++v) {
    for (const Frame& sent : vehicles_[v]->take_sent()) links_[v].bridge.offer(Side::vehicle, sent, t_end);
  }
  for (Link& link : links_) {
    while (link.bridge.deliver(Side::ground, t_end + kGridTolerance_s, f)) {
      ground_.push_back(f);
      ++link.downlink_delivered;
    }
  }
  MocapFrame m;
  while (lockstep_.plant().pop_mocap(m)) mocap_.push_back(m);
}

std::vector<Frame> Arena::take_ground_frames() {
  std::vector<Frame> out;
  out.swap(ground_);
  return out;
}

std::vector<MocapFrame> Arena::take_mocap() {
  std::vector<MocapFrame> out;
  out.swap(mocap_);
  return out;
}

RadioCounters Arena::radio(pa::VehicleId vehicle) const {
  const Link& link = links_[slot(vehicle)];
  RadioCounters c;
  c.uplink_offered = link.bridge.offered(Side::ground);
  c.uplink_lost = link.bridge.lost(Side::ground);
  c.uplink_delivered = link.uplink_delivered;
  c.downlink_offered = link.bridge.offered(Side::vehicle);
  c.downlink_lost = link.bridge.lost(Side::vehicle);
  c.downlink_delivered = link.downlink_delivered;
  return c;
}

}  // namespace hil::sil
