#include "hil/plant/randomisation.hpp"

#include "hil/plant/random.hpp"

namespace hil {

namespace {

constexpr std::string_view kGainKeys[2][4] = {
    {"vehicle1_motor0_gain", "vehicle1_motor1_gain", "vehicle1_motor2_gain", "vehicle1_motor3_gain"},
    {"vehicle2_motor0_gain", "vehicle2_motor1_gain", "vehicle2_motor2_gain", "vehicle2_motor3_gain"}};

// The draws both profiles record: each motor's gain, and the IMU's noise levels.
void append_motor_gains(std::vector<DrawnParameter>& out, const PlantConfig& c) {
  for (std::size_t v = 0; v < 2; ++v) {
    for (std::size_t m = 0; m < 4; ++m) out.push_back({kGainKeys[v][m], c.vehicle.motor_gain[v][m]});
  }
}
void append_imu_noise(std::vector<DrawnParameter>& out, const PlantConfig& c) {
  out.insert(out.end(), {{"imu_accel_noise_mps2", c.imu.accel_noise_mps2},
                         {"imu_gyro_noise_radps", c.imu.gyro_noise_radps},
                         {"imu_accel_bias_sigma_mps2", c.imu.accel_bias_sigma_mps2},
                         {"imu_gyro_bias_sigma_radps", c.imu.gyro_bias_sigma_radps}});
}

// x scaled by U(1 - fraction, 1 + fraction); the groups below are drawn alike by both profiles.
void scale(Random& rng, double& x, double fraction) { x *= rng.uniform(1.0 - fraction, 1.0 + fraction); }
void scale_pole_drag(Random& rng, PoleConfig& pole, double fraction) {
  scale(rng, pole.drag_axial_kgpm2, fraction);
  scale(rng, pole.drag_normal_kgpm2, fraction);
  scale(rng, pole.drag_rotational_kgpm2, fraction);
}
void scale_imu_noise(Random& rng, ImuConfig& imu, double fraction) {
  scale(rng, imu.accel_noise_mps2, fraction);
  scale(rng, imu.gyro_noise_radps, fraction);
  scale(rng, imu.accel_bias_sigma_mps2, fraction);
  scale(rng, imu.gyro_bias_sigma_radps, fraction);
}

// The arena envelope (EnvelopeConfig), on the same stream as the default profile: a seed gives
// one world per profile. What the envelope leaves out (each motor's mismatch, the vehicles'
// drag, the friction, the IMU's noise) is drawn with the default profile's spreads.
PlantConfig envelope_randomised(const PlantConfig& nominal, std::uint64_t seed) {
  Random rng(seed, RandomStream::randomisation);
  const RandomisationConfig& r = nominal.randomisation;
  const EnvelopeConfig& e = nominal.envelope;
  PlantConfig c = nominal;
  auto scale = [&rng](double& x, double fraction) { hil::scale(rng, x, fraction); };

  scale_pole_drag(rng, c.pole, e.pole_drag_fraction);
  scale(c.pole.mass_kg, e.pole_mass_fraction);
  scale(c.pole.half_length_m, e.pole_length_fraction);
  VehicleConfig& v = c.vehicle;
  for (std::size_t k = 0; k < 2; ++k) {
    v.thrust_scale[k] = rng.uniform(e.thrust_scale_min, e.thrust_scale_max);
    for (double& gain : v.motor_gain[k]) scale(gain, r.motor_gain_fraction);
    scale(v.mass_scale[k], e.mass_fraction);
    scale(v.inertia_scale[k], e.inertia_fraction);
    // The time constant itself is drawn; the scale carries it over the airframe's.
    const double tau_s = rng.uniform(e.motor_time_constant_min_s, e.motor_time_constant_max_s);
    v.motor_time_constant_scale[k] = v.motor_time_constant_s > 0.0 ? tau_s / v.motor_time_constant_s : 1.0;
    c.battery.charge_start[k] = rng.uniform(e.charge_start_min, e.charge_start_max);
  }
  scale(v.drag_Nspm, r.vehicle_drag_fraction);
  scale(c.contact.plate_friction, r.friction_fraction);
  scale(c.contact.floor_friction, r.friction_fraction);
  c.mocap.latency_s = rng.uniform(e.latency_min_s, e.latency_max_s);
  c.mocap.jitter_s = rng.uniform(0.0, e.jitter_max_s);
  c.mocap.position_noise_m = rng.uniform(e.position_noise_min_m, e.position_noise_max_m);
  c.mocap.attitude_noise_rad = rng.uniform(e.attitude_noise_min_rad, e.attitude_noise_max_rad);
  scale_imu_noise(rng, c.imu, r.noise_fraction);
  c.radio_loss_probability = rng.uniform(0.0, e.radio_loss_max);
  // Drawn last, so that adding it left every earlier draw of a seed as it was.
  c.pole.centre_of_mass_offset_m = rng.uniform(-e.pole_centre_of_mass_max_m, e.pole_centre_of_mass_max_m);
  return c;
}

std::vector<DrawnParameter> envelope_drawn_parameters(const PlantConfig& c) {
  const VehicleConfig& v = c.vehicle;
  std::vector<DrawnParameter> out = {
      {"pole_drag_axial_kgpm2", c.pole.drag_axial_kgpm2},
      {"pole_drag_normal_kgpm2", c.pole.drag_normal_kgpm2},
      {"pole_drag_rotational_kgpm2", c.pole.drag_rotational_kgpm2},
      {"pole_mass_kg", c.pole.mass_kg},
      {"pole_half_length_m", c.pole.half_length_m},
      {"pole_centre_of_mass_offset_m", c.pole.centre_of_mass_offset_m},
  };
  static constexpr std::string_view kKeys[2][5] = {
      {"vehicle1_thrust_scale", "vehicle1_mass_scale", "vehicle1_inertia_scale",
       "vehicle1_motor_time_constant_scale", "vehicle1_battery_charge_start"},
      {"vehicle2_thrust_scale", "vehicle2_mass_scale", "vehicle2_inertia_scale",
       "vehicle2_motor_time_constant_scale", "vehicle2_battery_charge_start"}};
  for (std::size_t k = 0; k < 2; ++k) {
    out.insert(out.end(), {{kKeys[k][0], v.thrust_scale[k]},
                           {kKeys[k][1], v.mass_scale[k]},
                           {kKeys[k][2], v.inertia_scale[k]},
                           {kKeys[k][3], v.motor_time_constant_scale[k]},
                           {kKeys[k][4], c.battery.charge_start[k]}});
  }
  append_motor_gains(out, c);
  out.insert(out.end(), {{"vehicle_drag_Nspm", v.drag_Nspm},
                         {"contact_plate_friction", c.contact.plate_friction},
                         {"contact_floor_friction", c.contact.floor_friction}});
  append_imu_noise(out, c);
  out.insert(out.end(), {
                            {"mocap_latency_s", c.mocap.latency_s},
                            {"mocap_jitter_s", c.mocap.jitter_s},
                            {"mocap_position_noise_m", c.mocap.position_noise_m},
                            {"mocap_attitude_noise_rad", c.mocap.attitude_noise_rad},
                            {"radio_loss_probability", c.radio_loss_probability},
                        });
  return out;
}

}  // namespace

PlantConfig randomised(const PlantConfig& nominal, std::uint64_t seed) {
  if (nominal.randomisation.profile == 1) return envelope_randomised(nominal, seed);
  Random rng(seed, RandomStream::randomisation);
  const RandomisationConfig& r = nominal.randomisation;
  PlantConfig c = nominal;
  // The draw order is fixed: changing it changes every recorded world.
  auto scale = [&rng](double& x, double fraction) { hil::scale(rng, x, fraction); };

  scale_pole_drag(rng, c.pole, r.drag_fraction);
  for (auto& vehicle : c.vehicle.motor_gain) {
    for (double& gain : vehicle) scale(gain, r.motor_gain_fraction);
  }
  scale(c.vehicle.motor_time_constant_s, r.motor_time_constant_fraction);
  scale(c.vehicle.drag_Nspm, r.vehicle_drag_fraction);
  scale(c.contact.plate_friction, r.friction_fraction);
  scale(c.contact.floor_friction, r.friction_fraction);
  c.mocap.latency_s = rng.uniform(r.latency_min_s, r.latency_max_s);
  scale(c.mocap.position_noise_m, r.noise_fraction);
  scale(c.mocap.attitude_noise_rad, r.noise_fraction);
  scale_imu_noise(rng, c.imu, r.noise_fraction);
  // Drawn after the others, so that adding them kept every earlier draw.
  scale(c.pole.mass_kg, r.pole_mass_fraction);
  scale(c.pole.half_length_m, r.pole_length_fraction);
  c.radio_loss_probability = rng.uniform(r.radio_loss_min, r.radio_loss_max);
  return c;
}

std::vector<DrawnParameter> drawn_parameters(const PlantConfig& c) {
  if (c.randomisation.profile == 1) return envelope_drawn_parameters(c);
  std::vector<DrawnParameter> out = {
      {"pole_drag_axial_kgpm2", c.pole.drag_axial_kgpm2},
      {"pole_drag_normal_kgpm2", c.pole.drag_normal_kgpm2},
      {"pole_drag_rotational_kgpm2", c.pole.drag_rotational_kgpm2},
  };
  append_motor_gains(out, c);
  out.insert(out.end(), {
                            {"vehicle_motor_time_constant_s", c.vehicle.motor_time_constant_s},
                            {"vehicle_drag_Nspm", c.vehicle.drag_Nspm},
                            {"contact_plate_friction", c.contact.plate_friction},
                            {"contact_floor_friction", c.contact.floor_friction},
                            {"mocap_latency_s", c.mocap.latency_s},
                            {"mocap_position_noise_m", c.mocap.position_noise_m},
                            {"mocap_attitude_noise_rad", c.mocap.attitude_noise_rad},
                        });
  append_imu_noise(out, c);
  out.insert(out.end(), {
                            {"pole_mass_kg", c.pole.mass_kg},
                            {"pole_half_length_m", c.pole.half_length_m},
                            {"radio_loss_probability", c.radio_loss_probability},
                        });
  return out;
}

}  // namespace hil
