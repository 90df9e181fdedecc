// The plant's configuration file: hil/config/plant.yaml documents every parameter with the
// built-in defaults, and bad input is reported with file and line instead of crashing.
#include <catch2/catch.hpp>

#include <fstream>
#include <sstream>
#include <string>

#include "hil/plant/plant.hpp"
#include "hil/plant/plant_config.hpp"

using hil::PlantConfig;

namespace {
std::string read(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}
}  // namespace

TEST_CASE("plant.yaml holds exactly the built-in defaults and names every parameter") {
  PlantConfig loaded;
  loaded.pole.mass_kg = 123.0;  // must be overwritten by the file
  std::string error;
  REQUIRE(hil::load_plant_config(hil::default_plant_config_path(), loaded, error));
  CHECK(error.empty());
  CHECK(hil::format_plant_config(loaded) == hil::format_plant_config(PlantConfig{}));

  const std::string text = read(hil::default_plant_config_path());
  for (const std::string_view key : hil::plant_config_keys()) {
    INFO(key);
    CHECK(text.find("\n" + std::string(key) + ": ") != std::string::npos);
  }
}

TEST_CASE("a formatted configuration loads back to the same values") {
  PlantConfig c;
  c.pole.drag_normal_kgpm2 = 4.2e-3;
  c.mocap.latency_s = 0.0137;
  c.vehicle.motor_gain[1][2] = 0.97;
  c.imu.rate_Hz = 500;
  PlantConfig back;
  std::string error;
  REQUIRE(hil::parse_plant_config(hil::format_plant_config(c), "formatted", back, error));
  CHECK(hil::format_plant_config(back) == hil::format_plant_config(c));
}

TEST_CASE("bad configuration lines are reported with file and line, and change nothing") {
  struct Case {
    const char* text;
    const char* message;
  };
  const Case cases[] = {
      {"pole_mass_kg: 0.03\nno_such_key: 1\n", "bad.yaml:2: unknown plant parameter 'no_such_key'"},
      {"# comment\n\npole_mass_kg: heavy\n", "bad.yaml:3: 'pole_mass_kg' needs a finite number, got 'heavy'"},
      {"pole_mass_kg: -1\n", "bad.yaml:1: 'pole_mass_kg' = -1 is outside > 0 .. 10"},
      {"pole_mass_kg: .nan\n", "bad.yaml:1: 'pole_mass_kg' needs a finite number"},
      {"pole_mass_kg: nan\n", "bad.yaml:1: 'pole_mass_kg' needs a finite number"},
      {"pole_mass_kg: .inf\n", "bad.yaml:1: 'pole_mass_kg' needs a finite number"},
      {"pole_mass_kg: 0.03 kg\n", "bad.yaml:1: 'pole_mass_kg' needs a finite number, got '0.03 kg'"},
      {"pole_mass_kg: [0.03]\n", "bad.yaml:1: 'pole_mass_kg' needs a finite number"},
      {"imu_rate_Hz: 1000.5\n", "bad.yaml:1: 'imu_rate_Hz' needs an integer"},
      {"mocap_latency_s 0.01\n", "bad.yaml:1: expected a map of `key: value` lines"},
      {"mocap_latency_s:\n", "bad.yaml:1: 'mocap_latency_s' needs a finite number"},
      {"pole_mass_kg: 0.03\npole_mass_kg: 0.04\n",
       "bad.yaml:2: 'pole_mass_kg' is given twice (first on line 1)"},
      {"pole_mass_kg: 0.03\nimu_rate_Hz: [1000\n", "bad.yaml:3: "},   // YAML syntax: the list is never closed
      {"pole_mass_kg: 0.03\n  imu_rate_Hz: 1000\n", "bad.yaml:2: "},  // YAML syntax: bad indentation
      {"integration_step_contact_s: 0.002\n", "bad.yaml: integration_step_contact_s must not exceed"},
      {"random_latency_min_s: 0.05\n", "bad.yaml: random_latency_min_s must not exceed random_latency_max_s"},
      {"\n\nmocap_dropout_probability: 1.5\n",
       "bad.yaml:3: 'mocap_dropout_probability' = 1.5 is outside 0 .. 1"},
  };
  for (const Case& c : cases) {
    INFO(c.text);
    PlantConfig config;
    std::string error;
    CHECK_FALSE(hil::parse_plant_config(c.text, "bad.yaml", config, error));
    INFO(error);
    CHECK(error.rfind(c.message, 0) == 0);
    CHECK(hil::format_plant_config(config) == hil::format_plant_config(PlantConfig{}));
  }
}

TEST_CASE("an empty configuration file keeps every default") {
  PlantConfig config;
  std::string error;
  CHECK(hil::parse_plant_config("# nothing but a comment\n", "empty.yaml", config, error));
  CHECK(hil::format_plant_config(config) == hil::format_plant_config(PlantConfig{}));
}

TEST_CASE("a missing configuration file is an error, not a crash") {
  PlantConfig config;
  std::string error;
  CHECK_FALSE(hil::load_plant_config("/nonexistent/plant.yaml", config, error));
  CHECK(error == "/nonexistent/plant.yaml: cannot read the file");
}

TEST_CASE("the plant refuses a configuration built in code with values out of range") {
  PlantConfig c;
  c.vehicle.mass_kg = 0.0;
  CHECK_THROWS_AS(hil::Plant(c), std::invalid_argument);
  CHECK(hil::check_plant_config(c).find("vehicle_mass_kg") != std::string::npos);
}
