#include "hil/plant/randomisation.hpp"

#include "hil/plant/random.hpp"

namespace hil {

PlantConfig randomised(const PlantConfig& nominal, std::uint64_t seed) {
  Random rng(seed, RandomStream::randomisation);
  const RandomisationConfig& r = nominal.randomisation;
  PlantConfig c = nominal;
  // The draw order is fixed: changing it changes every recorded world.
  auto scale = [&rng](double& x, double fraction) { x *= rng.uniform(1.0 - fraction, 1.0 + fraction); };

  scale(c.pole.drag_axial_kgpm2, r.drag_fraction);
  scale(c.pole.drag_normal_kgpm2, r.drag_fraction);
  scale(c.pole.drag_rotational_kgpm2, r.drag_fraction);
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
  scale(c.imu.accel_noise_mps2, r.noise_fraction);
  scale(c.imu.gyro_noise_radps, r.noise_fraction);
  scale(c.imu.accel_bias_sigma_mps2, r.noise_fraction);
  scale(c.imu.gyro_bias_sigma_radps, r.noise_fraction);
  // Drawn after the others, so that adding them kept every earlier draw.
  scale(c.pole.mass_kg, r.pole_mass_fraction);
  scale(c.pole.half_length_m, r.pole_length_fraction);
  c.radio_loss_probability = rng.uniform(r.radio_loss_min, r.radio_loss_max);
  return c;
}

std::vector<DrawnParameter> drawn_parameters(const PlantConfig& c) {
  std::vector<DrawnParameter> out = {
      {"pole_drag_axial_kgpm2", c.pole.drag_axial_kgpm2},
      {"pole_drag_normal_kgpm2", c.pole.drag_normal_kgpm2},
      {"pole_drag_rotational_kgpm2", c.pole.drag_rotational_kgpm2},
  };
  static constexpr std::string_view kGainKeys[2][4] = {
      {"vehicle1_motor0_gain", "vehicle1_motor1_gain", "vehicle1_motor2_gain", "vehicle1_motor3_gain"},
      {"vehicle2_motor0_gain", "vehicle2_motor1_gain", "vehicle2_motor2_gain", "vehicle2_motor3_gain"}};
  for (std::size_t v = 0; v < 2; ++v) {
    for (std::size_t m = 0; m < 4; ++m) out.push_back({kGainKeys[v][m], c.vehicle.motor_gain[v][m]});
  }
  out.insert(out.end(), {
                            {"vehicle_motor_time_constant_s", c.vehicle.motor_time_constant_s},
                            {"vehicle_drag_Nspm", c.vehicle.drag_Nspm},
                            {"contact_plate_friction", c.contact.plate_friction},
                            {"contact_floor_friction", c.contact.floor_friction},
                            {"mocap_latency_s", c.mocap.latency_s},
                            {"mocap_position_noise_m", c.mocap.position_noise_m},
                            {"mocap_attitude_noise_rad", c.mocap.attitude_noise_rad},
                            {"imu_accel_noise_mps2", c.imu.accel_noise_mps2},
                            {"imu_gyro_noise_radps", c.imu.gyro_noise_radps},
                            {"imu_accel_bias_sigma_mps2", c.imu.accel_bias_sigma_mps2},
                            {"imu_gyro_bias_sigma_radps", c.imu.gyro_bias_sigma_radps},
                            {"pole_mass_kg", c.pole.mass_kg},
                            {"pole_half_length_m", c.pole.half_length_m},
                            {"radio_loss_probability", c.radio_loss_probability},
                        });
  return out;
}

}  // namespace hil
