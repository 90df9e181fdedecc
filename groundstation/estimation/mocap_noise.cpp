#include "groundstation/estimation/mocap_noise.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace gs::estimation {
namespace {

bool finite(const MocapPose& p) { return p.p_m.allFinite() && p.q.coeffs().allFinite(); }

// The rotation vector of b relative to a, in a's body frame.
Eigen::Vector3d increment(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  const Eigen::AngleAxisd r(a.conjugate() * b);
  double angle = r.angle();
  if (angle > M_PI) angle -= 2.0 * M_PI;  // the short way
  return angle * r.axis();
}

// sigma from the median magnitude of a zero-mean normal of variance 6 sigma^2.
double sigma_from_median(const std::array<double, MocapNoiseMeter::kCapacity>& values, std::size_t n) {
  std::vector<double> copy(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(n));
  auto middle = copy.begin() + static_cast<std::ptrdiff_t>(n / 2);
  std::nth_element(copy.begin(), middle, copy.end());
  return *middle / (0.6745 * std::sqrt(6.0));
}

}  // namespace

void MocapNoiseMeter::add(double t_s, const MocapPose& pose, bool quiet) {
  if (!quiet || !std::isfinite(t_s) || !finite(pose)) {
    run_ = 0;
    return;
  }
  if (run_ > 0 && std::abs(t_s - t_s_[1] - period_s_) > 0.2 * period_s_) run_ = 0;
  if (run_ == 2) {
    const Eigen::Vector3d dd = pose.p_m - 2.0 * pose_[1].p_m + pose_[0].p_m;
    const Eigen::Vector3d da = increment(pose_[1].q, pose.q) - increment(pose_[0].q, pose_[1].q);
    for (int axis = 0; axis < 3; ++axis) push(std::abs(dd(axis)), std::abs(da(axis)));
  }
  if (run_ == 2 || run_ == 1) {
    pose_[0] = pose_[1];
    t_s_[0] = t_s_[1];
  }
  pose_[1] = pose;
  t_s_[1] = t_s;
  run_ = std::min(run_ + 1, 2);
}

void MocapNoiseMeter::push(double position_m, double attitude_rad) {
  position_[next_] = position_m;
  attitude_[next_] = attitude_rad;
  next_ = (next_ + 1) % kCapacity;
  count_ = std::min(count_ + 1, kCapacity);
}

std::optional<MocapNoise> MocapNoiseMeter::noise() const {
  if (count_ < kMinimum) return std::nullopt;
  return MocapNoise{sigma_from_median(position_, count_), sigma_from_median(attitude_, count_)};
}

}  // namespace gs::estimation
