// A vehicle's IMU: it reads the specific force (non-gravitational force over mass, in the body
// frame: +g on z when level at rest) and the body rates, each averaged over the sample period
// as the sensor's own integrating front end does, then adds a constant bias (drawn once per run
// from the seed), white noise, and clips to the sensor's range.
#pragma once

#include <array>
#include <cstdint>

#include "hil/plant/plant_config.hpp"
#include "hil/plant/random.hpp"
#include "hil/plant/types.hpp"

namespace hil {

struct ImuSample {
  double t_s = 0.0;
  std::uint64_t tick = 0;  // t_s = tick / imu_rate_Hz
  Vec3 gyro_radps = Vec3::Zero();
  Vec3 accel_mps2 = Vec3::Zero();
};

class ImuModel {
 public:
  ImuModel(const ImuConfig& config, std::uint64_t seed, RandomStream stream);

  ImuSample measure(std::uint64_t tick, double t_s, const Vec3& true_rate_radps,
                    const Vec3& true_specific_force_mps2);

  const Vec3& accel_bias_mps2() const { return accel_bias_; }
  const Vec3& gyro_bias_radps() const { return gyro_bias_; }

 private:
  ImuConfig config_;
  Random rng_;
  Vec3 accel_bias_;
  Vec3 gyro_bias_;
};

}  // namespace hil
