#include "groundstation/estimation/onboard_tilt.hpp"

#include <algorithm>
#include <cmath>

#include "pa/protocol.hpp"

namespace gs::estimation {

Eigen::Vector3d OnboardTilt::true_up_onboard(const Eigen::Quaterniond& onboard,
                                             const Eigen::Quaterniond& measured) {
  return onboard.normalized() * (measured.normalized().conjugate() * Eigen::Vector3d::UnitZ());
}

std::optional<Eigen::Vector2d> OnboardTilt::report(double t_s, const Eigen::Quaterniond& onboard,
                                                   const Eigen::Quaterniond& measured, double rate_radps) {
  if (!std::isfinite(t_s) || t_s < blocked_until_s_) return std::nullopt;
  const Eigen::Vector3d up = true_up_onboard(onboard, measured);
  if (!up.allFinite() || up.z() <= 0.0 || !(rate_radps < settings_.calm_rate_radps)) return std::nullopt;
  if (!window_start_s_) window_start_s_ = t_s;
  sum_ += up.head<2>() / up.z();
  ++count_;
  if (t_s - *window_start_s_ < settings_.window_s) return std::nullopt;

  const Eigen::Vector2d mean = sum_ / count_;
  const bool enough = count_ >= settings_.min_reports;
  window_start_s_.reset();
  sum_.setZero();
  count_ = 0;
  if (!enough) return std::nullopt;
  last_error_rad_ = std::atan(mean.norm());
  if (last_error_rad_ <= settings_.correct_above_rad) return std::nullopt;
  blocked_until_s_ = t_s + settings_.settle_s;
  return mean;
}

std::int32_t tilt_correction_argument(const Eigen::Vector2d& true_up_xy) {
  const auto counts = [](double v) {
    const double limit = pa::proto::kTiltMaxCounts;
    return static_cast<std::int16_t>(std::clamp(std::round(v / pa::proto::kTiltUnit), -limit, limit));
  };
  return pa::proto::tilt_argument(counts(true_up_xy.x()), counts(true_up_xy.y()));
}

}  // namespace gs::estimation
