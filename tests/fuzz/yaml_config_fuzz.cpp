// Fuzzes the YAML configuration readers through their string entry points: the plant parameters
// (hil/plant/plant_config), the scenarios (hil/plant/scenario) and the vehicle limits
// (groundstation/model/vehicle_limits). Every input goes to all three: a file of one kind is
// a corrupted file of the others.
//
// Invariants: no reader throws; a rejection is "name:..." with a message; an accepted plant
// configuration formats to text that parses back to the same configuration (format, parse,
// format gives the same text).
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "groundstation/model/vehicle_limits.hpp"
#include "hil/plant/plant_config.hpp"
#include "hil/plant/scenario.hpp"

namespace {

void check(bool condition) {
  if (!condition) __builtin_trap();
}

void check_error(const std::string& error, const std::string& name) {
  check(error.size() > name.size() + 1 && error.compare(0, name.size() + 1, name + ":") == 0);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  // A scenario may name its plant file; the reader follows the path it is given, which for a
  // device (/dev/zero, /dev/stdin) never ends. Files are not what this target fuzzes.
  if (text.find("/dev") != std::string_view::npos || text.find("/proc") != std::string_view::npos) return 0;

  {
    const std::string name = "plant.yaml";
    hil::PlantConfig config;
    std::string error;
    if (hil::parse_plant_config(text, name, config, error)) {
      const std::string formatted = hil::format_plant_config(config);
      hil::PlantConfig again;
      std::string error2;
      check(hil::parse_plant_config(formatted, "formatted", again, error2));
      check(hil::format_plant_config(again) == formatted);
    } else {
      check_error(error, name);
    }
  }
  {
    const std::string name = "scenario.yaml";
    hil::Scenario scenario;
    std::string error;
    // The shipped scenarios name hil/config/plant.yaml relative to their own directory.
    if (!hil::parse_scenario(text, name, PA_SOURCE_DIR "/hil/config/scenarios", scenario, error))
      check_error(error, name);
  }
  {
    const std::string name = "vehicle_limits.yaml";
    const gs::model::VehicleLimitsLoad load = gs::model::parse_vehicle_limits(text, name);
    if (load.ok) {
      check(load.limits.a_q_min_mps2 > 0 && load.limits.a_q_max_mps2 > load.limits.a_q_min_mps2 &&
            load.limits.omega_max_radps > 0);
    } else {
      check_error(load.error, name);
    }
  }
  return 0;
}
