// The modes of the hybrid pole estimator (Section IV): free flight (20), or resting on one of
// the two vehicles (30).
#pragma once

#include <array>
#include <optional>
#include <string_view>

#include "pa/vehicle_id.hpp"

namespace gs::estimation {

enum class PoleMode : int { free = 0, on_vehicle1 = 1, on_vehicle2 = 2 };
inline constexpr int kPoleModeCount = 3;
inline constexpr std::array<PoleMode, kPoleModeCount> kPoleModes = {PoleMode::free, PoleMode::on_vehicle1,
                                                                    PoleMode::on_vehicle2};

inline constexpr int mode_index(PoleMode m) { return static_cast<int>(m); }

// "free", "on_vehicle1", "on_vehicle2" (the CLI's and the telemetry's spelling).
std::string_view pole_mode_name(PoleMode mode);
std::optional<PoleMode> pole_mode_from_name(std::string_view name);

// The on-vehicle mode of pa::kVehicle1 or pa::kVehicle2, and back (none in free flight).
PoleMode on_vehicle_mode(pa::VehicleId vehicle);
std::optional<pa::VehicleId> vehicle_of_mode(PoleMode mode);

// The pole only changes between free flight and resting on a vehicle: it cannot pass from one
// vehicle to the other without flying.
bool pole_mode_transition_allowed(PoleMode from, PoleMode to);

}  // namespace gs::estimation
