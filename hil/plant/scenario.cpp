#include "hil/plant/scenario.hpp"

#include <cmath>
#include <sstream>

#include "pa/yaml_file.hpp"

namespace hil {

namespace {

std::optional<VehicleMode> parse_mode(std::string_view s) {
  if (s == "parked") return VehicleMode::parked;
  if (s == "hold") return VehicleMode::hold;
  if (s == "balance") return VehicleMode::balance;
  if (s == "thrower") return VehicleMode::thrower;
  return std::nullopt;
}

std::string directory_of(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? std::string(".") : path.substr(0, slash);
}

// Applies one non-plant key. Returns an error message (without file:line) or "".
std::string apply(Scenario& s, const pa::yaml::Entry& e, bool& position_given1, bool& position_given2) {
  const std::string& k = e.key;
  const std::string v = pa::yaml::text(e.value);
  auto real = [&](double& target, double lo, double hi) -> std::string {
    const auto x = pa::yaml::finite_number(e.value);
    if (!x) return "'" + k + "' needs a finite number, got '" + v + "'";
    if (*x < lo || *x > hi) {
      std::ostringstream m;
      m << "'" << k << "' = " << v << " is outside " << lo << " .. " << hi;
      return m.str();
    }
    target = *x;
    return {};
  };
  auto vec3 = [&](Vec3& target) -> std::string {
    const auto x = pa::yaml::numbers(e.value, 3);
    if (!x) return "'" + k + "' needs three numbers [x, y, z]";
    target = Vec3((*x)[0], (*x)[1], (*x)[2]);
    return {};
  };
  auto mode = [&](VehicleMode& target, bool any) -> std::string {
    const auto m = parse_mode(v);
    if (!m || (!any && *m != VehicleMode::hold && *m != VehicleMode::balance)) {
      return "'" + k + "' must be " + (any ? "parked, hold, balance or thrower" : "hold or balance") +
             ", got '" + v + "'";
    }
    target = *m;
    return {};
  };

  if (k == "name") {
    s.name = v;
    return {};
  }
  if (k == "description") return {};
  if (k == "duration_s") return real(s.duration_s, 0.001, 3600.0);
  if (k == "seed") {
    const auto x = pa::yaml::integer(e.value);
    if (!x || *x < 0) return "'seed' needs a non-negative integer, got '" + v + "'";
    s.seed = static_cast<std::uint64_t>(*x);
    return {};
  }
  if (k == "randomise") {
    const auto x = pa::yaml::boolean(e.value);
    if (!x) return "'randomise' needs true or false, got '" + v + "'";
    s.randomise = *x;
    return {};
  }
  for (int i = 0; i < 2; ++i) {
    const std::string prefix = i == 0 ? "vehicle1_" : "vehicle2_";
    if (k.rfind(prefix, 0) != 0) continue;
    const std::string rest = k.substr(prefix.size());
    ScenarioVehicle& veh = s.vehicle[i];
    if (rest == "mode") return mode(veh.mode, true);
    if (rest == "after_catch") return mode(veh.after_catch, false);
    if (rest == "yaw_rad") return real(veh.yaw_rad, -10.0, 10.0);
    if (rest == "position_m") {
      (i == 0 ? position_given1 : position_given2) = true;
      if (v == "auto") {
        veh.position_auto = true;
        return {};
      }
      veh.position_auto = false;
      return vec3(veh.position_m);
    }
  }
  if (k == "pole_start") {
    if (v == "launch") {
      s.pole_start = PoleStart::launch;
    } else if (v == "balanced") {
      s.pole_start = PoleStart::balanced;
    } else {
      return "'pole_start' must be launch or balanced, got '" + v + "'";
    }
    return {};
  }
  if (k == "launch_time_s") return real(s.launch_time_s, 0.0, 3600.0);
  if (k == "launch_reference") {
    if (v == "lower_end") {
      s.launch_reference = LaunchReference::lower_end;
    } else if (v == "centre") {
      s.launch_reference = LaunchReference::centre;
    } else {
      return "'launch_reference' must be lower_end or centre, got '" + v + "'";
    }
    return {};
  }
  if (k == "pole_position_m") return vec3(s.pole_position_m);
  if (k == "pole_velocity_mps") return vec3(s.pole_velocity_mps);
  if (k == "pole_tilt_rad") return real(s.pole_tilt_rad, -10.0, 10.0);
  if (k == "pole_tilt_rate_radps") return real(s.pole_tilt_rate_radps, -100.0, 100.0);
  if (k == "pole_tilt_heading_rad") return real(s.pole_tilt_heading_rad, -10.0, 10.0);
  if (k == "thrower_release_s") return real(s.thrower_release_s, 0.0, 10.0);
  if (k == "catch_height_m") return real(s.catch_height_m, 0.0, 100.0);
  if (k == "catch_offset_m") return vec3(s.catch_offset_m);
  if (k == "balance_vehicle") {
    const auto x = pa::yaml::integer(e.value);
    if (!x || (*x != 1 && *x != 2)) return "'balance_vehicle' must be 1 or 2, got '" + v + "'";
    s.balance_vehicle = pa::VehicleId(static_cast<std::uint8_t>(*x));
    return {};
  }
  if (k == "balance_tilt_rad") return real(s.balance_tilt_rad, -0.5, 0.5);
  if (k == "balance_lambda_radps") return real(s.balance_lambda_radps, 0.1, 20.0);
  return "unknown scenario key '" + k + "'";
}

}  // namespace

bool parse_scenario(std::string_view text, const std::string& name, const std::string& base_dir,
                    Scenario& out, std::string& error) {
  YAML::Node root;
  std::vector<pa::yaml::Entry> entries;
  if (!pa::yaml::parse_document(text, name, root, error)) return false;
  if (!root.IsNull() && !pa::yaml::entries_of(root, name, entries, error)) return false;
  Scenario s;
  s.source = name;

  // The plant configuration first, so that the `plant:` overrides apply on top of it wherever
  // they stand in the file.
  for (const pa::yaml::Entry& e : entries) {
    if (e.key != "plant_config") continue;
    const std::string file = pa::yaml::text(e.value);
    const std::string path = (!file.empty() && file[0] == '/') ? file : base_dir + "/" + file;
    std::string message;
    if (file.empty() || !load_plant_config(path, s.plant, message)) {
      error = pa::yaml::where(name, e) + "plant_config: " + (file.empty() ? "needs a file name" : message);
      return false;
    }
  }
  bool position_given[2] = {false, false};
  bool has_name = false;
  for (const pa::yaml::Entry& e : entries) {
    if (e.key == "plant_config") continue;
    if (e.key == "plant") {
      if (!apply_plant_entries(e.value, name, s.plant, error)) return false;
      continue;
    }
    if (e.key == "name") has_name = true;
    if (const std::string message = apply(s, e, position_given[0], position_given[1]); !message.empty()) {
      error = pa::yaml::where(name, e) + message;
      return false;
    }
  }
  if (!has_name) {
    error = name + ": 'name' is required";
    return false;
  }
  if (const std::string problem = check_plant_config(s.plant); !problem.empty()) {
    error = name + ": " + problem;
    return false;
  }
  for (int i = 0; i < 2; ++i) {
    const ScenarioVehicle& v = s.vehicle[i];
    const std::string key = i == 0 ? "vehicle1_position_m" : "vehicle2_position_m";
    if (v.mode != VehicleMode::parked && !position_given[i]) {
      error = name + ": '" + key + "' is required for a vehicle that flies";
      return false;
    }
    if (v.position_auto && (v.mode == VehicleMode::parked || v.mode == VehicleMode::thrower ||
                            s.pole_start != PoleStart::launch)) {
      error = name + ": '" + key + ": auto' needs a flying vehicle and pole_start: launch";
      return false;
    }
  }
  for (int i = 0; i < 2; ++i) {
    if (s.vehicle[i].mode == VehicleMode::thrower &&
        (s.pole_start != PoleStart::launch || s.vehicle[1 - i].mode == VehicleMode::thrower)) {
      error = name + ": vehicle" + std::to_string(i + 1) +
              "_mode: thrower needs pole_start: launch (and one thrower only)";
      return false;
    }
  }
  if (s.pole_start == PoleStart::balanced &&
      s.vehicle[pa::act_slot(s.balance_vehicle)].mode == VehicleMode::parked) {
    error = name + ": the pole is balanced on vehicle" + std::to_string(s.balance_vehicle.node()) +
            ", which is parked";
    return false;
  }
  if (s.pole_start == PoleStart::launch && s.launch_time_s > s.duration_s) {
    error = name + ": launch_time_s is after the end of the run (duration_s)";
    return false;
  }
  out = s;
  return true;
}

bool load_scenario(const std::string& path, Scenario& out, std::string& error) {
  std::string text;
  return pa::yaml::read_file(path, text, error) && parse_scenario(text, path, directory_of(path), out, error);
}

std::string scenario_directory() { return std::string(PA_HIL_CONFIG_DIR) + "/scenarios"; }

}  // namespace hil
