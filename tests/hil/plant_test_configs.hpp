// Plant configurations for the plant's tests: the defaults with one group of effects switched
// off, so that a test isolates the law it checks.
#pragma once

#include "hil/plant/plant_config.hpp"

namespace plant_test {

// No IMU noise and no IMU bias.
inline hil::PlantConfig without_imu_errors(hil::PlantConfig c = {}) {
  c.imu.accel_noise_mps2 = 0.0;
  c.imu.gyro_noise_radps = 0.0;
  c.imu.accel_bias_sigma_mps2 = 0.0;
  c.imu.gyro_bias_sigma_radps = 0.0;
  return c;
}

// No aerodynamic drag on the pole or the vehicles.
inline hil::PlantConfig without_drag(hil::PlantConfig c = {}) {
  c.pole.drag_axial_kgpm2 = 0.0;
  c.pole.drag_normal_kgpm2 = 0.0;
  c.pole.drag_rotational_kgpm2 = 0.0;
  c.vehicle.drag_Nspm = 0.0;
  return c;
}

// No motion-capture noise.
inline hil::PlantConfig without_mocap_noise(hil::PlantConfig c = {}) {
  c.mocap.position_noise_m = 0.0;
  c.mocap.attitude_noise_rad = 0.0;
  return c;
}

}  // namespace plant_test
