// The motion capture's noise, measured from the poses themselves. At 200 Hz the second
// difference of a body's position, x[k+1] - 2 x[k] + x[k-1], is its acceleration times dt^2
// (12 um at 0.5 m/s^2 in hover) plus the noise's n[k+1] - 2 n[k] + n[k-1], of variance 6 sigma^2
// for independent noise of sigma per axis. So sigma is read off the spread of second
// differences, with no model of the body, as long as it is not accelerating hard: the median of
// their magnitudes per axis is 0.6745 sqrt(6) sigma, which a few bursts (a gust, a dropout's
// gap) hardly move. The attitude alike, on the rotation vectors of consecutive increments. An
// arena's calibration reports this figure too; measuring it needs no one to copy it over.
#pragma once

#include <array>
#include <cstddef>
#include <optional>

#include <Eigen/Geometry>

#include "groundstation/estimation/mocap_pose.hpp"

namespace gs::estimation {

struct MocapNoise {
  double position_sigma_m = 0.0;
  double attitude_sigma_rad = 0.0;
};

class MocapNoiseMeter {
 public:
  // The newest second differences kept (per axis, position and attitude alike): 8 s of hover.
  static constexpr std::size_t kCapacity = 4800;
  static constexpr std::size_t kMinimum = 600;  // before this many, no estimate

  explicit MocapNoiseMeter(double frame_period_s = 0.005) : period_s_(frame_period_s) {}

  // A pose of the body at t_s. Three in a row one frame period apart (within 20 %) make a
  // second difference; a gap, a non-finite pose or `quiet` false (the body accelerating on
  // purpose: a throw, a catch) starts the run of three over.
  void add(double t_s, const MocapPose& pose, bool quiet);
  // nullopt until kMinimum second differences of each kind.
  std::optional<MocapNoise> noise() const;
  std::size_t samples() const { return count_; }

 private:
  void push(double position_m, double attitude_rad);

  double period_s_;
  std::array<double, 2> t_s_{};
  std::array<MocapPose, 2> pose_{};
  int run_ = 0;  // consecutive poses held (0, 1, 2)
  std::array<double, kCapacity> position_{};
  std::array<double, kCapacity> attitude_{};
  std::size_t next_ = 0;
  std::size_t count_ = 0;
};

}  // namespace gs::estimation
