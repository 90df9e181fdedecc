#include "hil/plant/plant_config.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

#include "pa/yaml_file.hpp"

namespace hil {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// One parameter: its key, where it lives, and its admissible range. `lo_open` excludes lo.
struct Parameter {
  std::string_view key;
  double& (*real)(PlantConfig&);
  int& (*integer)(PlantConfig&);
  double lo;
  double hi;
  bool lo_open;
};

template <int V, int M>
double& motor_gain(PlantConfig& c) {
  return c.vehicle.motor_gain[V][M];
}

#define PA_REAL(name, member, lo, hi, open)                                         \
  Parameter {                                                                       \
    name, [](PlantConfig& c) -> double& { return c.member; }, nullptr, lo, hi, open \
  }
#define PA_INT(name, member, lo, hi)                                              \
  Parameter {                                                                     \
    name, nullptr, [](PlantConfig& c) -> int& { return c.member; }, lo, hi, false \
  }

const Parameter kParameters[] = {
    PA_REAL("gravity_mps2", gravity_mps2, 0.0, 100.0, false),
    PA_REAL("air_density_kgpm3", air_density_kgpm3, 0.0, 10.0, true),
    PA_REAL("pole_half_length_m", pole.half_length_m, 0.0, 10.0, true),
    PA_REAL("pole_mass_kg", pole.mass_kg, 0.0, 10.0, true),
    PA_REAL("pole_radius_m", pole.radius_m, 0.0, 0.1, true),
    PA_REAL("pole_drag_axial_kgpm2", pole.drag_axial_kgpm2, 0.0, 1.0, false),
    PA_REAL("pole_drag_normal_kgpm2", pole.drag_normal_kgpm2, 0.0, 1.0, false),
    PA_REAL("pole_drag_rotational_kgpm2", pole.drag_rotational_kgpm2, 0.0, 1.0, false),
    PA_INT("pole_drag_segments", pole.drag_segments, 1, 1000),
    PA_REAL("pole_centre_of_mass_offset_m", pole.centre_of_mass_offset_m, -0.1, 0.1, false),
    PA_REAL("vehicle_mass_kg", vehicle.mass_kg, 0.0, 100.0, true),
    PA_REAL("vehicle_inertia_xx_kgm2", vehicle.inertia_xx_kgm2, 0.0, 10.0, true),
    PA_REAL("vehicle_inertia_yy_kgm2", vehicle.inertia_yy_kgm2, 0.0, 10.0, true),
    PA_REAL("vehicle_inertia_zz_kgm2", vehicle.inertia_zz_kgm2, 0.0, 10.0, true),
    PA_REAL("vehicle_arm_length_m", vehicle.arm_length_m, 0.0, 5.0, true),
    PA_REAL("vehicle_yaw_moment_per_thrust_m", vehicle.yaw_moment_per_thrust_m, 0.0, 1.0, false),
    PA_REAL("vehicle_motor_thrust_max_N", vehicle.motor_thrust_max_N, 0.0, 1000.0, true),
    PA_REAL("vehicle_motor_time_constant_s", vehicle.motor_time_constant_s, 0.0, 1.0, false),
    PA_REAL("vehicle_rotor_radius_m", vehicle.rotor_radius_m, 0.0, 5.0, true),
    PA_REAL("vehicle_propulsion_efficiency", vehicle.propulsion_efficiency, 0.0, 1.0, true),
    PA_REAL("vehicle_drag_Nspm", vehicle.drag_Nspm, 0.0, 100.0, false),
    PA_REAL("vehicle_foot_depth_m", vehicle.foot_depth_m, 0.0, 1.0, false),
    PA_REAL("vehicle_plate_radius_m", vehicle.plate_radius_m, 0.0, 1.0, true),
    PA_REAL("vehicle_plate_height_m", vehicle.plate_height_m, -1.0, 1.0, false),
    Parameter{"vehicle1_motor0_gain", motor_gain<0, 0>, nullptr, 0.0, 2.0, false},
    Parameter{"vehicle1_motor1_gain", motor_gain<0, 1>, nullptr, 0.0, 2.0, false},
    Parameter{"vehicle1_motor2_gain", motor_gain<0, 2>, nullptr, 0.0, 2.0, false},
    Parameter{"vehicle1_motor3_gain", motor_gain<0, 3>, nullptr, 0.0, 2.0, false},
    Parameter{"vehicle2_motor0_gain", motor_gain<1, 0>, nullptr, 0.0, 2.0, false},
    Parameter{"vehicle2_motor1_gain", motor_gain<1, 1>, nullptr, 0.0, 2.0, false},
    Parameter{"vehicle2_motor2_gain", motor_gain<1, 2>, nullptr, 0.0, 2.0, false},
    Parameter{"vehicle2_motor3_gain", motor_gain<1, 3>, nullptr, 0.0, 2.0, false},
    PA_REAL("vehicle1_thrust_scale", vehicle.thrust_scale[0], 0.0, 2.0, true),
    PA_REAL("vehicle2_thrust_scale", vehicle.thrust_scale[1], 0.0, 2.0, true),
    PA_REAL("vehicle1_mass_scale", vehicle.mass_scale[0], 0.0, 10.0, true),
    PA_REAL("vehicle2_mass_scale", vehicle.mass_scale[1], 0.0, 10.0, true),
    PA_REAL("vehicle1_inertia_scale", vehicle.inertia_scale[0], 0.0, 10.0, true),
    PA_REAL("vehicle2_inertia_scale", vehicle.inertia_scale[1], 0.0, 10.0, true),
    PA_REAL("vehicle1_motor_time_constant_scale", vehicle.motor_time_constant_scale[0], 0.0, 10.0, false),
    PA_REAL("vehicle2_motor_time_constant_scale", vehicle.motor_time_constant_scale[1], 0.0, 10.0, false),
    PA_INT("battery_enabled", battery.enabled, 0, 1),
    PA_INT("battery_cells", battery.cells, 1, 14),
    PA_REAL("battery_capacity_Ah", battery.capacity_Ah, 0.0, 100.0, true),
    PA_REAL("battery_internal_resistance_ohm", battery.internal_resistance_ohm, 0.0, 10.0, false),
    PA_REAL("battery_reference_voltage_V", battery.reference_voltage_V, 0.0, 100.0, true),
    PA_REAL("vehicle1_battery_charge_start", battery.charge_start[0], 0.0, 1.0, false),
    PA_REAL("vehicle2_battery_charge_start", battery.charge_start[1], 0.0, 1.0, false),
    PA_REAL("contact_plate_stiffness_Npm", contact.plate_stiffness_Npm, 0.0, 1e7, true),
    PA_REAL("contact_plate_damping_Nspm", contact.plate_damping_Nspm, 0.0, 1e5, false),
    PA_REAL("contact_plate_damping_force_max_N", contact.plate_damping_force_max_N, 0.0, 1e6, true),
    PA_REAL("contact_plate_rebound_damping_Nspm", contact.plate_rebound_damping_Nspm, 0.0, 1e5, false),
    PA_REAL("contact_plate_friction", contact.plate_friction, 0.0, 10.0, false),
    PA_REAL("contact_plate_tangential_stiffness_Npm", contact.plate_tangential_stiffness_Npm, 0.0, 1e7, true),
    PA_REAL("contact_plate_tangential_damping_Nspm", contact.plate_tangential_damping_Nspm, 0.0, 1e5, false),
    PA_REAL("contact_floor_height_m", contact.floor_height_m, -100.0, 100.0, false),
    PA_REAL("contact_floor_stiffness_Npm", contact.floor_stiffness_Npm, 0.0, 1e7, true),
    PA_REAL("contact_floor_damping_Nspm", contact.floor_damping_Nspm, 0.0, 1e5, false),
    PA_REAL("contact_floor_damping_force_max_N", contact.floor_damping_force_max_N, 0.0, 1e6, true),
    PA_REAL("contact_floor_rebound_damping_Nspm", contact.floor_rebound_damping_Nspm, 0.0, 1e5, false),
    PA_REAL("contact_floor_friction", contact.floor_friction, 0.0, 10.0, false),
    PA_REAL("contact_floor_tangential_stiffness_Npm", contact.floor_tangential_stiffness_Npm, 0.0, 1e7, true),
    PA_REAL("contact_floor_tangential_damping_Nspm", contact.floor_tangential_damping_Nspm, 0.0, 1e5, false),
    PA_INT("imu_rate_Hz", imu.rate_Hz, 1, 100000),
    PA_REAL("imu_accel_noise_mps2", imu.accel_noise_mps2, 0.0, 100.0, false),
    PA_REAL("imu_gyro_noise_radps", imu.gyro_noise_radps, 0.0, 10.0, false),
    PA_REAL("imu_accel_bias_sigma_mps2", imu.accel_bias_sigma_mps2, 0.0, 100.0, false),
    PA_REAL("imu_gyro_bias_sigma_radps", imu.gyro_bias_sigma_radps, 0.0, 10.0, false),
    PA_REAL("imu_accel_range_mps2", imu.accel_range_mps2, 0.0, 1e4, true),
    PA_REAL("imu_gyro_range_radps", imu.gyro_range_radps, 0.0, 1e3, true),
    PA_INT("mocap_rate_Hz", mocap.rate_Hz, 1, 10000),
    PA_REAL("mocap_latency_s", mocap.latency_s, 0.0, 10.0, false),
    PA_REAL("mocap_jitter_s", mocap.jitter_s, 0.0, 10.0, false),
    PA_REAL("mocap_position_noise_m", mocap.position_noise_m, 0.0, 1.0, false),
    PA_REAL("mocap_attitude_noise_rad", mocap.attitude_noise_rad, 0.0, 1.0, false),
    PA_REAL("mocap_dropout_probability", mocap.dropout_probability, 0.0, 1.0, false),
    PA_REAL("mocap_dropout_outage_s", mocap.dropout_outage_s, 0.0, 10.0, false),
    PA_REAL("integration_step_free_s", integration.step_free_s, 0.0, 0.01, true),
    PA_REAL("integration_step_contact_s", integration.step_contact_s, 0.0, 0.01, true),
    PA_INT("integration_contact_step_by_mass", integration.contact_step_by_mass, 0, 1),
    PA_REAL("random_drag_fraction", randomisation.drag_fraction, 0.0, 0.99, false),
    PA_REAL("random_motor_gain_fraction", randomisation.motor_gain_fraction, 0.0, 0.99, false),
    PA_REAL("random_motor_time_constant_fraction", randomisation.motor_time_constant_fraction, 0.0, 0.99,
            false),
    PA_REAL("random_vehicle_drag_fraction", randomisation.vehicle_drag_fraction, 0.0, 0.99, false),
    PA_REAL("random_friction_fraction", randomisation.friction_fraction, 0.0, 0.99, false),
    PA_REAL("random_latency_min_s", randomisation.latency_min_s, 0.0, 10.0, false),
    PA_REAL("random_latency_max_s", randomisation.latency_max_s, 0.0, 10.0, false),
    PA_REAL("random_noise_fraction", randomisation.noise_fraction, 0.0, 0.99, false),
    PA_REAL("random_pole_mass_fraction", randomisation.pole_mass_fraction, 0.0, 0.5, false),
    PA_REAL("random_pole_length_fraction", randomisation.pole_length_fraction, 0.0, 0.5, false),
    PA_REAL("random_radio_loss_min", randomisation.radio_loss_min, 0.0, 1.0, false),
    PA_REAL("random_radio_loss_max", randomisation.radio_loss_max, 0.0, 1.0, false),
    PA_INT("random_profile", randomisation.profile, 0, 1),
    PA_REAL("envelope_thrust_scale_min", envelope.thrust_scale_min, 0.0, 2.0, true),
    PA_REAL("envelope_thrust_scale_max", envelope.thrust_scale_max, 0.0, 2.0, true),
    PA_REAL("envelope_charge_start_min", envelope.charge_start_min, 0.0, 1.0, false),
    PA_REAL("envelope_charge_start_max", envelope.charge_start_max, 0.0, 1.0, false),
    PA_REAL("envelope_motor_time_constant_min_s", envelope.motor_time_constant_min_s, 0.0, 1.0, false),
    PA_REAL("envelope_motor_time_constant_max_s", envelope.motor_time_constant_max_s, 0.0, 1.0, false),
    PA_REAL("envelope_mass_fraction", envelope.mass_fraction, 0.0, 0.5, false),
    PA_REAL("envelope_inertia_fraction", envelope.inertia_fraction, 0.0, 0.5, false),
    PA_REAL("envelope_pole_drag_fraction", envelope.pole_drag_fraction, 0.0, 0.99, false),
    PA_REAL("envelope_pole_length_fraction", envelope.pole_length_fraction, 0.0, 0.5, false),
    PA_REAL("envelope_pole_mass_fraction", envelope.pole_mass_fraction, 0.0, 0.5, false),
    PA_REAL("envelope_pole_centre_of_mass_max_m", envelope.pole_centre_of_mass_max_m, 0.0, 0.1, false),
    PA_REAL("envelope_latency_min_s", envelope.latency_min_s, 0.0, 10.0, false),
    PA_REAL("envelope_latency_max_s", envelope.latency_max_s, 0.0, 10.0, false),
    PA_REAL("envelope_jitter_max_s", envelope.jitter_max_s, 0.0, 10.0, false),
    PA_REAL("envelope_position_noise_min_m", envelope.position_noise_min_m, 0.0, 1.0, false),
    PA_REAL("envelope_position_noise_max_m", envelope.position_noise_max_m, 0.0, 1.0, false),
    PA_REAL("envelope_attitude_noise_min_rad", envelope.attitude_noise_min_rad, 0.0, 1.0, false),
    PA_REAL("envelope_attitude_noise_max_rad", envelope.attitude_noise_max_rad, 0.0, 1.0, false),
    PA_REAL("envelope_radio_loss_max", envelope.radio_loss_max, 0.0, 1.0, false),
    PA_REAL("radio_loss_probability", radio_loss_probability, 0.0, 1.0, false),
    PA_REAL("radio_outage_s", radio_outage_s, 0.0, 10.0, false),
    PA_INT("losses_only_in_pole_flight", losses_only_in_pole_flight, 0, 1),
};

#undef PA_REAL
#undef PA_INT

const Parameter* find_parameter(std::string_view key) {
  for (const Parameter& p : kParameters) {
    if (p.key == key) return &p;
  }
  return nullptr;
}

std::string range_text(const Parameter& p) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "%s%g .. %g", p.lo_open ? "> " : "", p.lo, p.hi);
  return buf;
}

}  // namespace

std::vector<std::string_view> plant_config_keys() {
  std::vector<std::string_view> keys;
  for (const Parameter& p : kParameters) keys.push_back(p.key);
  return keys;
}

bool set_plant_parameter(PlantConfig& config, std::string_view key, const YAML::Node& value,
                         std::string& error) {
  const Parameter* p = find_parameter(key);
  if (!p) {
    error = "unknown plant parameter '" + std::string(key) + "'";
    return false;
  }
  double v = 0.0;
  if (p->real) {
    const auto parsed = pa::yaml::finite_number(value);
    if (!parsed) {
      error = "'" + std::string(key) + "' needs a finite number, got '" + pa::yaml::text(value) + "'";
      return false;
    }
    v = *parsed;
  } else {
    const auto parsed = pa::yaml::integer(value);
    if (!parsed) {
      error = "'" + std::string(key) + "' needs an integer, got '" + pa::yaml::text(value) + "'";
      return false;
    }
    v = static_cast<double>(*parsed);
  }
  const bool below = p->lo_open ? !(v > p->lo) : !(v >= p->lo);
  if (below || !(v <= p->hi)) {
    error = "'" + std::string(key) + "' = " + pa::yaml::text(value) + " is outside " + range_text(*p);
    return false;
  }
  if (p->real) {
    p->real(config) = v;
  } else {
    p->integer(config) = static_cast<int>(v);
  }
  return true;
}

std::string check_plant_config(const PlantConfig& c) {
  PlantConfig copy = c;  // the accessors take a mutable reference
  for (const Parameter& p : kParameters) {
    const double v = p.real ? p.real(copy) : static_cast<double>(p.integer(copy));
    const bool below = p.lo_open ? !(v > p.lo) : !(v >= p.lo);
    if (below || !(v <= p.hi)) {
      char buf[64];
      std::snprintf(buf, sizeof buf, "%g", v);
      return std::string(p.key) + " = " + buf + " is outside " + range_text(p);
    }
  }
  if (c.integration.step_contact_s > c.integration.step_free_s)
    return "integration_step_contact_s must not exceed integration_step_free_s";
  if (c.randomisation.latency_min_s > c.randomisation.latency_max_s)
    return "random_latency_min_s must not exceed random_latency_max_s";
  if (c.randomisation.radio_loss_min > c.randomisation.radio_loss_max)
    return "random_radio_loss_min must not exceed random_radio_loss_max";
  if (c.vehicle.plate_height_m < -c.vehicle.foot_depth_m)
    return "the plate must not lie below the vehicle's feet";
  const EnvelopeConfig& e = c.envelope;
  const struct {
    double lo, hi;
    const char* what;
  } ranges[] = {
      {e.thrust_scale_min, e.thrust_scale_max,
       "envelope_thrust_scale_min must not exceed envelope_thrust_scale_max"},
      {e.charge_start_min, e.charge_start_max,
       "envelope_charge_start_min must not exceed envelope_charge_start_max"},
      {e.motor_time_constant_min_s, e.motor_time_constant_max_s,
       "envelope_motor_time_constant_min_s must not exceed envelope_motor_time_constant_max_s"},
      {e.latency_min_s, e.latency_max_s, "envelope_latency_min_s must not exceed envelope_latency_max_s"},
      {e.position_noise_min_m, e.position_noise_max_m,
       "envelope_position_noise_min_m must not exceed envelope_position_noise_max_m"},
      {e.attitude_noise_min_rad, e.attitude_noise_max_rad,
       "envelope_attitude_noise_min_rad must not exceed envelope_attitude_noise_max_rad"},
  };
  for (const auto& r : ranges) {
    if (r.lo > r.hi) return r.what;
  }
  return {};
}

bool apply_plant_entries(const YAML::Node& map, const std::string& name, PlantConfig& config,
                         std::string& error) {
  std::vector<pa::yaml::Entry> entries;
  if (!pa::yaml::entries_of(map, name, entries, error)) return false;
  PlantConfig updated = config;
  for (const pa::yaml::Entry& e : entries) {
    std::string message;
    if (!set_plant_parameter(updated, e.key, e.value, message)) {
      error =
          (find_parameter(e.key) ? pa::yaml::where(name, e) : name + ":" + std::to_string(e.line) + ": ") +
          message;
      return false;
    }
  }
  if (const std::string problem = check_plant_config(updated); !problem.empty()) {
    error = name + ": " + problem;
    return false;
  }
  config = updated;
  return true;
}

bool parse_plant_config(std::string_view text, const std::string& name, PlantConfig& config,
                        std::string& error) {
  YAML::Node root;
  if (!pa::yaml::parse_document(text, name, root, error)) return false;
  if (root.IsNull()) return true;  // an empty file: every parameter keeps its value
  return apply_plant_entries(root, name, config, error);
}

bool load_plant_config(const std::string& path, PlantConfig& config, std::string& error) {
  std::string text;
  return pa::yaml::read_file(path, text, error) && parse_plant_config(text, path, config, error);
}

std::string format_plant_config(const PlantConfig& config) {
  PlantConfig copy = config;  // the accessors take a mutable reference
  std::string text;
  char buf[160];
  for (const Parameter& p : kParameters) {
    if (p.real) {
      // The shortest form that reads back to the same double.
      const double v = p.real(copy);
      char number[40];
      for (int digits = 15; digits <= 17; ++digits) {
        std::snprintf(number, sizeof number, "%.*g", digits, v);
        if (std::strtod(number, nullptr) == v) break;
      }
      std::snprintf(buf, sizeof buf, "%.*s: %s\n", static_cast<int>(p.key.size()), p.key.data(), number);
    } else {
      std::snprintf(buf, sizeof buf, "%.*s: %d\n", static_cast<int>(p.key.size()), p.key.data(),
                    p.integer(copy));
    }
    text += buf;
  }
  return text;
}

std::string default_plant_config_path() { return std::string(PA_HIL_CONFIG_DIR) + "/plant.yaml"; }

}  // namespace hil
