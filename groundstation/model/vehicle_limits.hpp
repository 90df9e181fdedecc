// The quadrocopter input limits, eq. (1) and (2), and their loader from the documented
// YAML file groundstation/config/vehicle_limits.yaml (the paper leaves the values open;
// the file justifies them from docs/paper-notes.md). The loader never throws: errors come back with the
// file name and line number.
#pragma once

#include <string>
#include <string_view>

#include "groundstation/model/vehicle.hpp"

namespace gs::model {

struct VehicleLimits {
  double a_q_min_mps2 = 0.0;     // eq. (1), > 0
  double a_q_max_mps2 = 0.0;     // eq. (1), > a_q_min
  double omega_max_radps = 0.0;  // eq. (2), > 0, per body axis
  bool operator==(const VehicleLimits&) const = default;
};

struct VehicleLimitsLoad {
  bool ok = false;
  VehicleLimits limits;
  std::string error;  // "<source>:<line>: <what>" (or "<source>: <what>") when !ok
};

// Parses the text (YAML) of a limits file; `source_name` is used in error messages.
VehicleLimitsLoad parse_vehicle_limits(std::string_view text, std::string_view source_name);
// Reads and parses a limits file.
VehicleLimitsLoad load_vehicle_limits(const std::string& path);

// The repository's file relative to the repository root.
inline constexpr const char* kVehicleLimitsRelativePath = "groundstation/config/vehicle_limits.yaml";

// Eq. (1) and (2).
bool input_within_limits(const VehicleInput& input, const VehicleLimits& limits);
// The input clamped into the box of eq. (1) and (2), axis by axis.
VehicleInput saturate_input(const VehicleInput& input, const VehicleLimits& limits);

}  // namespace gs::model
