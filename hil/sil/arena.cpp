#include "hil/sil/arena.hpp"

#include <stdexcept>
#include <string>

#include "hil/run/radio_routing.hpp"

namespace hil::sil {

using pa::proto::Frame;

Arena::Arena(const PlantConfig& plant, const ArenaConfig& config, std::uint64_t seed)
    : exchange_(plant, config.radio, seed, pa::kActVehicles.size()) {
  firmware_.reserve(pa::kActVehicles.size());
  for (const pa::VehicleId v : pa::kActVehicles) {
    fw::VehicleConfig firmware = firmware_config_for(plant.vehicle, v, plant.battery.reference_voltage_V);
    firmware.link.session_nonce = static_cast<std::uint32_t>(run::mix_seed(seed ^ (0x200u + v.node())) >> 32);
    firmware_.emplace_back(firmware);
  }
}

const FirmwareVehicle& Arena::vehicle(pa::VehicleId vehicle) const {
  if (!pa::is_act_vehicle(vehicle))
    throw std::out_of_range("no arena vehicle has node " + std::to_string(vehicle.node()) + " (1 or 2)");
  return firmware_[pa::act_slot(vehicle)];
}

void Arena::step() {
  exchange_.step();
  for (FirmwareVehicle& firmware : firmware_) {
    const pa::VehicleId v = firmware.vehicle();
    for (const Frame& sent : firmware.on_bus(exchange_.take_vehicle_frames(v)))
      exchange_.on_vehicle_frame(v, sent);
  }
}

}  // namespace hil::sil
