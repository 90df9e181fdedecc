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
    if (config.emulated_firmware) {
      firmware_.emplace_back(firmware, *config.emulated_firmware);
    } else {
      firmware_.emplace_back(firmware);
    }
  }
}

const FirmwareVehicle& Arena::vehicle(pa::VehicleId vehicle) const {
  if (!pa::is_act_vehicle(vehicle))
    throw std::out_of_range("no arena vehicle has node " + std::to_string(vehicle.node()) + " (1 or 2)");
  return firmware_[pa::act_slot(vehicle)];
}

void Arena::step() {
  exchange_.step();
  // Every firmware gets its bus before any answer is read (emulated images run at the same
  // time); a vehicle's bus and its answers touch no other vehicle's link, so this is the order
  // of one vehicle after the other.
  for (FirmwareVehicle& firmware : firmware_)
    firmware.write_bus(exchange_.take_vehicle_frames(firmware.vehicle()));
  for (FirmwareVehicle& firmware : firmware_) {
    const pa::VehicleId v = firmware.vehicle();
    for (const Frame& sent : firmware.read_answer()) exchange_.on_vehicle_frame(v, sent);
  }
}

}  // namespace hil::sil
