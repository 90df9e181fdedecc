#include "groundstation/estimation/pole_length.hpp"

#include <cmath>

namespace gs::estimation {

std::optional<double> pole_half_length_sample(const MocapPose& vehicle, const MocapPose& pole,
                                              double plate_height_m, const PoleLengthParams& params) {
  if (!is_usable_pose(vehicle) || !is_usable_pose(pole)) return std::nullopt;
  const Eigen::Vector3d z = vehicle.q.normalized() * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d plate = vehicle.p_m + plate_height_m * z;
  const Eigen::Vector3d n = pole_direction_from_quaternion(pole.q.normalized());
  const double cos_tilt = std::abs(n.dot(z));
  if (cos_tilt < std::cos(params.max_axis_tilt_rad)) return std::nullopt;
  const double height_m = (pole.p_m - plate).dot(z);
  const double length_m = height_m / cos_tilt;
  const double nominal = params.nominal_m;
  if (!(std::abs(length_m - nominal) <= params.plausible_fraction * nominal)) return std::nullopt;
  // n points either way along the pole; the lower end is the one towards the plate.
  const Eigen::Vector3d up = n.dot(z) > 0.0 ? n : Eigen::Vector3d(-n);
  const Eigen::Vector3d lower_end = pole.p_m - length_m * up;
  if ((lower_end - plate).norm() > params.max_radial_m) return std::nullopt;
  return length_m;
}

bool PoleLengthLearner::add(double sample_m) {
  if (!std::isfinite(sample_m) ||
      std::abs(sample_m - params_.nominal_m) > params_.plausible_fraction * params_.nominal_m)
    return false;
  if (learnt() && std::abs(sample_m - mean_m_) > params_.consistency_m) return false;
  if (count_ < params_.max_samples) ++count_;
  mean_m_ += (sample_m - mean_m_) / count_;
  return true;
}

std::optional<double> PoleLengthLearner::learnt() const {
  if (count_ < params_.samples_to_learn) return std::nullopt;
  return mean_m_;
}

std::optional<double> PoleLengthLearner::estimate() const {
  if (count_ == 0) return std::nullopt;
  return mean_m_;
}

}  // namespace gs::estimation
