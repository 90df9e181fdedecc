// The modes of the hybrid pole estimator (Section IV): free flight (20), or resting on one of
// the two vehicles (30).
#pragma once

#include <array>
#include <optional>
#include <string_view>

namespace gs::estimation {

enum class PoleMode : int { free = 0, on_vehicle1 = 1, on_vehicle2 = 2 };
inline constexpr int kPoleModeCount = 3;
inline constexpr std::array<PoleMode, kPoleModeCount> kPoleModes = {PoleMode::free, PoleMode::on_vehicle1,
                                                                    PoleMode::on_vehicle2};

inline constexpr int modeIndex(PoleMode m) { return static_cast<int>(m); }

// "free", "on_vehicle1", "on_vehicle2" (the CLI's and the telemetry's spelling).
std::string_view poleModeName(PoleMode mode);
std::optional<PoleMode> poleModeFromName(std::string_view name);

// The on-vehicle mode of vehicle 1 or 2, and back (0 for free flight).
PoleMode onVehicleMode(int vehicle);
int vehicleOfMode(PoleMode mode);

// The pole only changes between free flight and resting on a vehicle: it cannot pass from one
// vehicle to the other without flying.
bool poleModeTransitionAllowed(PoleMode from, PoleMode to);

}  // namespace gs::estimation
