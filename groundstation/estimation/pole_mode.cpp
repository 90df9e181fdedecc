#include "groundstation/estimation/pole_mode.hpp"

namespace gs::estimation {

std::string_view poleModeName(PoleMode mode) {
  switch (mode) {
    case PoleMode::free: return "free";
    case PoleMode::on_vehicle1: return "on_vehicle1";
    case PoleMode::on_vehicle2: return "on_vehicle2";
  }
  return "free";
}

std::optional<PoleMode> poleModeFromName(std::string_view name) {
  for (PoleMode m : kPoleModes) {
    if (poleModeName(m) == name) return m;
  }
  return std::nullopt;
}

PoleMode onVehicleMode(int vehicle) { return vehicle == 2 ? PoleMode::on_vehicle2 : PoleMode::on_vehicle1; }

int vehicleOfMode(PoleMode mode) {
  return mode == PoleMode::on_vehicle1 ? 1 : mode == PoleMode::on_vehicle2 ? 2 : 0;
}

bool poleModeTransitionAllowed(PoleMode from, PoleMode to) {
  return from != to && (from == PoleMode::free || to == PoleMode::free);
}

}  // namespace gs::estimation
