// Deterministic random numbers for the plant: the same seed gives the same draws on every
// platform. std::mt19937_64 is specified bit for bit; the standard distributions are not, so
// the uniform and Gaussian draws are computed here. Each consumer (each IMU, the motion
// capture, the randomisation) gets its own stream derived from the run's seed and a stream
// number, so adding draws to one never shifts the others.
#pragma once

#include <cstdint>
#include <random>

namespace hil {

// Stream numbers, fixed so that recorded runs stay reproducible.
enum class RandomStream : std::uint64_t { randomisation = 1, imu_vehicle1 = 2, imu_vehicle2 = 3, mocap = 4 };

class Random {
 public:
  Random(std::uint64_t seed, RandomStream stream);

  double uniform();                      // [0, 1)
  double uniform(double lo, double hi);  // [lo, hi)
  double gaussian();                     // standard normal
  double gaussian(double sigma) { return sigma * gaussian(); }

 private:
  std::mt19937_64 engine_;
  bool have_spare_ = false;
  double spare_ = 0.0;
};

}  // namespace hil
