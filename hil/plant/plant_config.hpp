// Every parameter of the truth plant, with its default. hil/config/plant.yaml documents each
// one (unit and source) and holds the same values; a test keeps the two equal.
//
// The defaults describe the paper's arena (Section VII-A: pole, plate, drag coefficients, 200 Hz
// motion capture) and, where the paper is silent, a modified AscTec Hummingbird with the same
// figures as firmware/core/include/fw/config.hpp - but the plant reads its own file, so the
// firmware and the ground station can be tested against a world that differs from their models.
#pragma once

#include <array>
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "hil/plant/types.hpp"

namespace hil {

struct PoleConfig {
  double half_length_m = 0.665;  // L (2L = 1.33 m, Section VII-A)
  double mass_kg = 0.03;         // m_p (Section VII-A)
  double radius_m = 0.005;       // carbon tube radius: gives the small axial inertia m r^2
  // Drag per unit length, force = c |v| v (eqs. (10)-(15)), kg/m^2.
  double drag_axial_kgpm2 = 0.5e-3;       // c_z
  double drag_normal_kgpm2 = 3.5e-3;      // c_xy
  double drag_rotational_kgpm2 = 2.1e-3;  // c_rot
  int drag_segments = 20;                 // quadrature segments along the pole
  // The centre of mass along n from the middle, towards end 1: end caps and absorbers differ.
  // The motion capture's markers give the middle; the ground station takes it as the centre.
  double centre_of_mass_offset_m = 0.0;

  // Where end `end` lies along n from the centre of mass (end 0 below it on a balanced pole).
  double end_along_axis_m(int end) const {
    return (end == 0 ? -half_length_m : half_length_m) - centre_of_mass_offset_m;
  }
  // The longer of the two levers from the centre of mass to an end.
  double longest_lever_m() const { return half_length_m + std::abs(centre_of_mass_offset_m); }
};

// Pole end `end` of `pole`.
inline Vec3 pole_end_m(const PoleState& pole, const PoleConfig& config, int end) {
  return pole.point_m(config.end_along_axis_m(end));
}

struct VehicleConfig {
  double mass_kg = 0.52;
  double inertia_xx_kgm2 = 2.5e-3;
  double inertia_yy_kgm2 = 2.5e-3;
  double inertia_zz_kgm2 = 4.5e-3;
  double arm_length_m = 0.17;              // centre to each motor, X layout
  double yaw_moment_per_thrust_m = 0.016;  // rotor drag torque / thrust
  double motor_thrust_max_N = 3.2;         // at command 1 (with gain 1)
  double motor_time_constant_s = 0.03;     // first-order lag of each motor's thrust
  double drag_Nspm = 0.1;                  // linear translational (rotor) drag
  double foot_depth_m = 0.05;              // landing feet below the CG, under the motors
  double plate_radius_m = 0.06;            // catching plate, 0.12 m across (Section VII-A)
  double plate_height_m = 0.03;            // plate surface above the CG (Section VII-A)
  // Per-motor thrust gain (actual / nominal thrust), vehicle 1 and vehicle 2.
  std::array<std::array<double, 4>, 2> motor_gain{{{1.0, 1.0, 1.0, 1.0}, {1.0, 1.0, 1.0, 1.0}}};
  // Each vehicle as built against the airframe above (vehicle 1, vehicle 2), factors on its
  // values; 1 is the airframe file. Thrust: at full charge (with the battery), on every motor.
  std::array<double, 2> thrust_scale{1.0, 1.0};
  std::array<double, 2> mass_scale{1.0, 1.0};
  std::array<double, 2> inertia_scale{1.0, 1.0};  // all three principal moments
  std::array<double, 2> motor_time_constant_scale{1.0, 1.0};
  // The electrical power of a motor making thrust T (battery.hpp): T^1.5 / (eta sqrt(2 rho A)),
  // A = pi r^2 the rotor disc.
  double rotor_radius_m = 0.1;
  double propulsion_efficiency = 0.45;  // eta: rotor figure of merit x motor x ESC
};

// The battery of each vehicle (battery.hpp): a LiPo pack whose open-circuit voltage follows its
// state of charge, sagging by I R under load; the motors' thrust goes with the square of the
// voltage. Off (0), the motors make exactly the thrust of the airframe file, as before.
struct BatteryConfig {
  int enabled = 0;
  int cells = 3;                                 // in series: 12.6 V full, 11.1 V nominal
  double capacity_Ah = 2.1;                      // 2100 mAh
  double internal_resistance_ohm = 0.04;         // the pack's with its wiring
  double reference_voltage_V = 12.6;             // where motor_thrust_max_N is made
  std::array<double, 2> charge_start{1.0, 1.0};  // state of charge at the start, vehicle 1, 2
};

// Compliant (penalty) contact (contact_law.hpp): a spring and dampers along the normal, and a
// tangential spring-damper to an anchor point that slides once the force reaches the Coulomb
// limit (stick and slip).
struct ContactConfig {
  double plate_stiffness_Npm = 1000.0;  // the pole end's shock absorber on the plate
  double plate_damping_Nspm = 20.0;
  double plate_damping_force_max_N = 12.0;
  double plate_rebound_damping_Nspm = 40.0;
  double plate_friction = 0.6;
  double plate_tangential_stiffness_Npm = 2000.0;
  double plate_tangential_damping_Nspm = 8.0;
  double floor_height_m = 0.0;
  double floor_stiffness_Npm = 5000.0;  // per contact point (pole end, vehicle foot)
  double floor_damping_Nspm = 50.0;
  double floor_damping_force_max_N = 500.0;
  double floor_rebound_damping_Nspm = 50.0;
  double floor_friction = 0.8;
  double floor_tangential_stiffness_Npm = 5000.0;
  double floor_tangential_damping_Nspm = 50.0;
};

struct ImuConfig {
  int rate_Hz = 1000;
  double accel_noise_mps2 = 0.05;  // white noise per sample, 1 sigma per axis
  double gyro_noise_radps = 0.003;
  double accel_bias_sigma_mps2 = 0.1;  // constant bias per run, drawn per axis from the seed
  double gyro_bias_sigma_radps = 0.005;
  double accel_range_mps2 = 156.9064;  // +-16 g
  double gyro_range_radps = 34.9;      // +-2000 deg/s (HIL_IMU_GYRO carries +-36 rad/s)
};

struct MocapConfig {
  int rate_Hz = 200;                  // Section VII-A
  double latency_s = 0.010;           // capture to delivery
  double jitter_s = 0.0;              // uniform in [0, jitter_s] on top, delivered in order
  double position_noise_m = 0.001;    // 1 sigma per axis
  double attitude_noise_rad = 0.001;  // 1 sigma per axis of a small body-frame rotation
  double dropout_probability = 0.0;   // per body per frame
  // > 0: each body's dropouts come as outages of this length, dropout_probability the fraction
  // of the time it is hidden (hil/plant/outages.hpp); 0: frame by frame.
  double dropout_outage_s = 0.0;
};

struct IntegrationConfig {
  double step_free_s = 0.001;      // RK4 step with no contact near
  double step_contact_s = 0.0001;  // during and just before contact, for the stiffest case
  // 1: a pole end's contact step grows with the end's effective mass (plant.hpp); 0: always
  // step_contact_s (the reference the longer steps are tested against).
  int contact_step_by_mass = 1;
};

// The spreads of the uncertain parameters, used by randomised() (randomisation.hpp).
struct RandomisationConfig {
  double drag_fraction = 0.3;         // each c scaled by U(1 -+ f)
  double motor_gain_fraction = 0.05;  // each motor gain scaled by U(1 -+ f)
  double motor_time_constant_fraction = 0.2;
  double vehicle_drag_fraction = 0.3;
  double friction_fraction = 0.2;
  double latency_min_s = 0.005;  // motion-capture latency drawn from U(min, max)
  double latency_max_s = 0.020;
  double noise_fraction = 0.5;         // every noise sigma scaled by U(1 -+ f)
  double pole_mass_fraction = 0.03;    // the pole's mass scaled by U(1 -+ f)
  double pole_length_fraction = 0.02;  // the pole's length scaled by U(1 -+ f)
  double radio_loss_min = 0.0;         // radio_loss_probability drawn from U(min, max)
  double radio_loss_max = 0.02;
  // 0: randomised() draws the spreads above; 1: the arena envelope (EnvelopeConfig).
  int profile = 0;
};

// The arena envelope: as wide as real vehicles and arenas (randomisation.hpp). Ranges are
// uniform; a fraction f scales the nominal value by U(1 - f, 1 + f).
struct EnvelopeConfig {
  double thrust_scale_min = 0.85;  // each vehicle's thrust at full charge, of the airframe's
  double thrust_scale_max = 1.05;
  double charge_start_min = 0.7;  // each battery's state of charge at the start
  double charge_start_max = 1.0;
  double motor_time_constant_min_s = 0.02;  // each vehicle's motors
  double motor_time_constant_max_s = 0.06;
  double mass_fraction = 0.1;       // each vehicle's mass
  double inertia_fraction = 0.2;    // each vehicle's inertia
  double pole_drag_fraction = 0.4;  // each pole drag coefficient
  double pole_length_fraction = 0.03;
  double pole_mass_fraction = 0.05;
  double pole_centre_of_mass_max_m = 0.01;  // the offset drawn from U(-max, max)
  double latency_min_s = 0.005;             // motion capture
  double latency_max_s = 0.04;
  double jitter_max_s = 0.004;  // jitter drawn from U(0, max)
  double position_noise_min_m = 0.0005;
  double position_noise_max_m = 0.003;
  double attitude_noise_min_rad = 0.0005;
  double attitude_noise_max_rad = 0.003;
  double radio_loss_max = 0.05;  // radio_loss_probability drawn from U(0, max)
};

struct PlantConfig {
  double gravity_mps2 = 9.81;
  PoleConfig pole{};
  VehicleConfig vehicle{};
  ContactConfig contact{};
  ImuConfig imu{};
  MocapConfig mocap{};
  IntegrationConfig integration{};
  RandomisationConfig randomisation{};
  BatteryConfig battery{};
  EnvelopeConfig envelope{};
  double air_density_kgpm3 = 1.225;  // for the rotors' power (VehicleConfig)
  // The probability that an arena radio loses a frame, each direction (RadioConfig::loss; a
  // campaign's arena takes it from its drawn plant).
  double radio_loss_probability = 0.0;
  // > 0: the radios lose frames in outages of this length (both directions at once),
  // radio_loss_probability the fraction of the time they are out (RadioConfig::outage_s).
  double radio_outage_s = 0.0;
  // 1: the radios' losses and the motion capture's dropouts happen only while the pole flies
  // (touches nothing: thrown and not yet caught or down), the fault of a radio that fades just
  // when the catch needs it; 0: all the time (Plant::losses_active()).
  int losses_only_in_pole_flight = 0;
};

// Names of all keys, in the order of the table (for documentation checks).
std::vector<std::string_view> plant_config_keys();

// Sets one parameter from its YAML value. Returns false with a message (without file:line) for
// an unknown key, a malformed value or a value outside the parameter's range.
bool set_plant_parameter(PlantConfig& config, std::string_view key, const YAML::Node& value,
                         std::string& error);
// Cross-parameter checks (e.g. the contact step not longer than the free step). Empty if fine.
std::string check_plant_config(const PlantConfig& config);

// Applies a YAML map of `key: value` (a plant file's top level, or a scenario's `plant:` map)
// over `config`, all or nothing. False with "name:line: message"; never throws.
bool apply_plant_entries(const YAML::Node& map, const std::string& name, PlantConfig& config,
                         std::string& error);

// Reads the YAML file `path` over `config` (keys absent from the file keep their values).
// Returns false with "path:line: message" on any error (YAML syntax, unknown key, malformed
// number, value out of range); never throws.
bool load_plant_config(const std::string& path, PlantConfig& config, std::string& error);
bool parse_plant_config(std::string_view text, const std::string& name, PlantConfig& config,
                        std::string& error);

// All parameters as YAML `key: value` lines, loadable again.
std::string format_plant_config(const PlantConfig& config);

// The default plant.yaml in the source tree.
std::string default_plant_config_path();

}  // namespace hil
