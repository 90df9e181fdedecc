#include "hil/run/radio_routing.hpp"

namespace hil::run {

RadioConfig with_plant_losses(RadioConfig radio, const PlantConfig& plant) {
  radio.loss = plant.radio_loss_probability;
  radio.outage_s = plant.radio_outage_s;
  return radio;
}

RadioConfig arena_radio_config(RadioConfig radio, std::uint64_t arena_seed, pa::VehicleId vehicle) {
  // The top half: splitmix64's best-mixed bits.
  radio.seed = static_cast<std::uint32_t>(
      mix_seed(mix_seed(arena_seed) ^ ((0x100u + vehicle.node()) * 0xD1B54A32D192ED03ull)) >> 32);
  return radio;
}

std::array<bool, 2> radios_carrying(const pa::proto::Frame& frame) {
  const std::uint8_t node = pa::proto::id_node(frame.id);
  if (node == pa::proto::kBroadcastNode) return {true, true};
  std::array<bool, 2> carrying{false, false};
  if (pa::is_act_vehicle(pa::VehicleId(node))) carrying[pa::act_slot(pa::VehicleId(node))] = true;
  return carrying;
}

std::uint64_t mix_seed(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

}  // namespace hil::run
