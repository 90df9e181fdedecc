#include "hil/plant/imu.hpp"

#include <algorithm>

namespace hil {

ImuModel::ImuModel(const ImuConfig& config, std::uint64_t seed, RandomStream stream)
    : config_(config), rng_(seed, stream) {
  for (int i = 0; i < 3; ++i) accel_bias_[i] = rng_.gaussian(config.accel_bias_sigma_mps2);
  for (int i = 0; i < 3; ++i) gyro_bias_[i] = rng_.gaussian(config.gyro_bias_sigma_radps);
}

ImuSample ImuModel::measure(std::uint64_t tick, double t_s, const Vec3& true_rate_radps,
                            const Vec3& true_specific_force_mps2) {
  ImuSample s;
  s.tick = tick;
  s.t_s = t_s;
  for (int i = 0; i < 3; ++i) {
    const double gyro = true_rate_radps[i] + gyro_bias_[i] + rng_.gaussian(config_.gyro_noise_radps);
    const double accel =
        true_specific_force_mps2[i] + accel_bias_[i] + rng_.gaussian(config_.accel_noise_mps2);
    s.gyro_radps[i] = std::clamp(gyro, -config_.gyro_range_radps, config_.gyro_range_radps);
    s.accel_mps2[i] = std::clamp(accel, -config_.accel_range_mps2, config_.accel_range_mps2);
  }
  return s;
}

}  // namespace hil
