#include "groundstation/estimation/pole_mode.hpp"

namespace gs::estimation {

std::string_view pole_mode_name(PoleMode mode) {
  switch (mode) {
    case PoleMode::free: return "free";
    case PoleMode::on_vehicle1: return "on_vehicle1";
    case PoleMode::on_vehicle2: return "on_vehicle2";
  }
  return "free";
}

std::optional<PoleMode> pole_mode_from_name(std::string_view name) {
  for (PoleMode m : kPoleModes) {
    if (pole_mode_name(m) == name) return m;
  }
  return std::nullopt;
}

PoleMode on_vehicle_mode(pa::VehicleId vehicle) {
  return vehicle == pa::kVehicle2 ? PoleMode::on_vehicle2 : PoleMode::on_vehicle1;
}

std::optional<pa::VehicleId> vehicle_of_mode(PoleMode mode) {
  if (mode == PoleMode::on_vehicle1) return pa::kVehicle1;
  if (mode == PoleMode::on_vehicle2) return pa::kVehicle2;
  return std::nullopt;
}

bool pole_mode_transition_allowed(PoleMode from, PoleMode to) {
  return from != to && (from == PoleMode::free || to == PoleMode::free);
}

}  // namespace gs::estimation
