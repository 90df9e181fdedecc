#include "groundstation/model/vehicle_limits.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

namespace gs::model {
namespace {

std::string_view trim(std::string_view s) {
  const auto is_space = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
  while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
  return s;
}

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

VehicleLimitsLoad parseVehicleLimits(std::string_view text, std::string_view source_name) {
  VehicleLimits limits;
  int seen_at_line[kKeyCount] = {};
  int line_number = 0;
  while (!text.empty()) {
    const std::size_t eol = text.find('\n');
    std::string_view line = text.substr(0, eol);
    text = eol == std::string_view::npos ? std::string_view{} : text.substr(eol + 1);
    ++line_number;
    if (const std::size_t hash = line.find('#'); hash != std::string_view::npos) {
      line = line.substr(0, hash);
    }
    line = trim(line);
    if (line.empty()) continue;
    const std::size_t eq = line.find('=');
    if (eq == std::string_view::npos) {
      return failure(source_name, line_number, "expected `key = value`, got `" +
                                                   std::string(line) + "`");
    }
    const std::string_view key = trim(line.substr(0, eq));
    const std::string_view value_text = trim(line.substr(eq + 1));
    int index = -1;
    for (int i = 0; i < kKeyCount; ++i) {
      if (key == kKeys[i].name) index = i;
    }
    if (index < 0) {
      return failure(source_name, line_number, "unknown key `" + std::string(key) + "`");
    }
    if (seen_at_line[index] != 0) {
      return failure(source_name, line_number,
                     "duplicate key `" + std::string(key) + "` (first at line " +
                         std::to_string(seen_at_line[index]) + ")");
    }
    double value = 0.0;
    const char* begin = value_text.data();
    const char* end = value_text.data() + value_text.size();
    const auto [ptr, ec] = std::from_chars(begin, end, value);
    if (value_text.empty() || ec != std::errc{} || ptr != end || !std::isfinite(value)) {
      return failure(source_name, line_number,
                     "value of `" + std::string(key) + "` is not a finite number: `" +
                         std::string(value_text) + "`");
    }
    limits.*(kKeys[index].field) = value;
    seen_at_line[index] = line_number;
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

VehicleLimitsLoad loadVehicleLimits(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return failure(path, 0, "cannot open file");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) return failure(path, 0, "read error");
  return parseVehicleLimits(buffer.str(), path);
}

bool inputWithinLimits(const VehicleInput& input, const VehicleLimits& limits) {
  if (!(input.a_q_mps2 >= limits.a_q_min_mps2 && input.a_q_mps2 <= limits.a_q_max_mps2)) {
    return false;
  }
  for (int i = 0; i < 3; ++i) {
    if (!(std::abs(input.omega_radps[i]) <= limits.omega_max_radps)) return false;
  }
  return true;
}

VehicleInput saturateInput(const VehicleInput& input, const VehicleLimits& limits) {
  VehicleInput out;
  out.a_q_mps2 = std::clamp(input.a_q_mps2, limits.a_q_min_mps2, limits.a_q_max_mps2);
  for (int i = 0; i < 3; ++i) {
    out.omega_radps[i] =
        std::clamp(input.omega_radps[i], -limits.omega_max_radps, limits.omega_max_radps);
  }
  return out;
}

}  // namespace gs::model
