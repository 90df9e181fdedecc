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
  return c;
}

}  // namespace hil
