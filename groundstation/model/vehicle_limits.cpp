#include "groundstation/model/vehicle_limits.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <optional>
#include <sstream>
#include <vector>

#include "pa/yaml_file.hpp"

namespace gs::model {
namespace {

VehicleLimitsLoad failure(std::string_view source, int line, const std::string& what) {
  VehicleLimitsLoad result;
  result.error = std::string(source);
  if (line > 0) result.error += ":" + std::to_string(line);
  result.error += ": " + what;
  return result;
}

struct Key {
  const char* name;
  double VehicleLimits::*field;
};
constexpr Key kKeys[] = {{"a_q_min_mps2", &VehicleLimits::a_q_min_mps2},
                         {"a_q_max_mps2", &VehicleLimits::a_q_max_mps2},
                         {"omega_max_radps", &VehicleLimits::omega_max_radps}};
constexpr int kKeyCount = static_cast<int>(sizeof(kKeys) / sizeof(kKeys[0]));

}  // namespace

VehicleLimitsLoad parse_vehicle_limits(std::string_view text, std::string_view source_name) {
  const std::string source(source_name);
  VehicleLimits limits;
  int seen_at_line[kKeyCount] = {};
  YAML::Node root;
  std::vector<pa::yaml::Entry> entries;
  std::string error;
  if (!pa::yaml::parse_document(text, source, root, error) ||
      (!root.IsNull() && !pa::yaml::entries_of(root, source, entries, error))) {
    VehicleLimitsLoad result;
    result.error = error;
    return result;
  }
  for (const pa::yaml::Entry& e : entries) {
    int index = -1;
    for (int i = 0; i < kKeyCount; ++i) {
      if (e.key == kKeys[i].name) index = i;
    }
    if (index < 0) return failure(source_name, e.line, "unknown key `" + e.key + "`");
    const std::optional<double> value = pa::yaml::finite_number(e.value);
    if (!value) {
      return failure(source_name, e.line,
                     "value of `" + e.key + "` is not a finite number: `" + pa::yaml::text(e.value) + "`");
    }
    limits.*(kKeys[index].field) = *value;
    seen_at_line[index] = e.line;
  }
  for (int i = 0; i < kKeyCount; ++i) {
    if (seen_at_line[i] == 0) {
      return failure(source_name, 0, std::string("missing key `") + kKeys[i].name + "`");
    }
  }
  // Eq. (1) needs 0 < a_q,min <= a_q,max; a degenerate (equal) box is allowed by (1) but useless
  // to a planner, so it is rejected too.
  if (!(limits.a_q_min_mps2 > 0.0)) {
    return failure(source_name, seen_at_line[0], "a_q_min_mps2 must be > 0 (eq. 1)");
  }
  if (!(limits.a_q_max_mps2 > limits.a_q_min_mps2)) {
    return failure(source_name, seen_at_line[1], "a_q_max_mps2 must exceed a_q_min_mps2 (eq. 1)");
  }
  if (!(limits.omega_max_radps > 0.0)) {
    return failure(source_name, seen_at_line[2], "omega_max_radps must be > 0 (eq. 2)");
  }
  VehicleLimitsLoad result;
  result.ok = true;
  result.limits = limits;
  return result;
}

VehicleLimitsLoad load_vehicle_limits(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return failure(path, 0, "cannot open file");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) return failure(path, 0, "read error");
  return parse_vehicle_limits(buffer.str(), path);
}

bool input_within_limits(const VehicleInput& input, const VehicleLimits& limits) {
  if (!(input.a_q_mps2 >= limits.a_q_min_mps2 && input.a_q_mps2 <= limits.a_q_max_mps2)) {
    return false;
  }
  for (int i = 0; i < 3; ++i) {
    if (!(std::abs(input.omega_radps[i]) <= limits.omega_max_radps)) return false;
  }
  return true;
}

VehicleInput saturate_input(const VehicleInput& input, const VehicleLimits& limits) {
  VehicleInput out;
  out.a_q_mps2 = std::clamp(input.a_q_mps2, limits.a_q_min_mps2, limits.a_q_max_mps2);
  for (int i = 0; i < 3; ++i) {
    out.omega_radps[i] = std::clamp(input.omega_radps[i], -limits.omega_max_radps, limits.omega_max_radps);
  }
  return out;
}

}  // namespace gs::model
