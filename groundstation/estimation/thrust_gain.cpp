#include "groundstation/estimation/thrust_gain.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "pa/constants.hpp"

namespace gs::estimation {

ThrustGainEstimator::ThrustGainEstimator(const ThrustGainConfig& config)
    : config_(config), gain_(config.initial_gain), variance_(config.initial_sigma * config.initial_sigma) {}

void ThrustGainEstimator::reset(double gain, double sigma) {
  gain_ = std::clamp(gain, config_.min_gain, config_.max_gain);
  variance_ = sigma * sigma;
}

double ThrustGainEstimator::sigma() const { return std::sqrt(variance_); }

void ThrustGainEstimator::command(double t_acts_s, double thrust_mps2) {
  if (!std::isfinite(t_acts_s) || !std::isfinite(thrust_mps2)) return;
  if (!commands_.empty() && t_acts_s < commands_.back().t_s) commands_.clear();  // time went back
  // Bounded: a ground station that stops sending poses keeps the latest commands only.
  if (commands_.size() >= 64) commands_.erase(commands_.begin());
  commands_.push_back({t_acts_s, thrust_mps2});
}

// The motors' thrust at t_s: each command from the time it acts, through the first-order lag.
void ThrustGainEstimator::advance_thrust(double t_s) {
  const auto step = [&](double to_s) {
    if (thrust_started_ && to_s > thrust_t_s_)
      thrust_mps2_ =
          acting_thrust_mps2_ + (thrust_mps2_ - acting_thrust_mps2_) *
                                    std::exp(-(to_s - thrust_t_s_) / config_.motor_time_constant_s);
    thrust_t_s_ = std::max(thrust_t_s_, to_s);
  };
  std::size_t used = 0;
  for (const Command& c : commands_) {
    if (c.t_s > t_s) break;
    step(c.t_s);
    if (!thrust_started_) thrust_mps2_ = c.thrust_mps2;
    acting_thrust_mps2_ = c.thrust_mps2;
    thrust_started_ = true;
    ++used;
  }
  commands_.erase(commands_.begin(), commands_.begin() + static_cast<std::ptrdiff_t>(used));
  step(t_s);
}

void ThrustGainEstimator::pose(double t_s, double z_m, double body_z_up, double extra_load_mps2,
                               bool usable) {
  if (!std::isfinite(t_s) || !std::isfinite(z_m) || !std::isfinite(body_z_up) ||
      !std::isfinite(extra_load_mps2))
    usable = false;
  else advance_thrust(t_s);
  const double thrust_up = thrust_mps2_ * body_z_up;
  usable = usable && thrust_started_ && thrust_mps2_ >= config_.min_thrust_mps2 &&
           body_z_up >= config_.min_vertical;
  if (!usable || (!window_.empty() && t_s <= window_.back().t_s)) {
    window_.clear();
    return;
  }
  window_.push_back({t_s, z_m, thrust_up, extra_load_mps2});
  if (t_s - window_.front().t_s >= config_.window_s) {
    if (window_.size() >= config_.min_poses) measure();
    window_.clear();
  }
}

// The window's mean vertical acceleration (twice the curvature of the least-squares parabola
// through its heights) against the mean thrust along the vertical that acted over it.
void ThrustGainEstimator::measure() {
  const double n = static_cast<double>(window_.size());
  double t_mean = 0.0, thrust = 0.0, load = 0.0;
  for (const Sample& s : window_) {
    t_mean += s.t_s / n;
    thrust += s.thrust_up_mps2 / n;
    load += s.load_mps2 / n;
  }
  Eigen::Matrix3d ata = Eigen::Matrix3d::Zero();
  Eigen::Vector3d atz = Eigen::Vector3d::Zero();
  for (const Sample& s : window_) {
    const double t = s.t_s - t_mean;
    const Eigen::Vector3d row(1.0, t, t * t);
    ata += row * row.transpose();
    atz += row * s.z_m;
  }
  const Eigen::Vector3d coefficients = ata.ldlt().solve(atz);
  if (std::abs(coefficients(1)) > config_.max_vertical_speed_mps) return;
  const double accel = 2.0 * coefficients(2);
  if (std::abs(accel) > config_.max_vertical_accel_mps2) {
    ++rejected_;
    return;
  }
  const double t_s = window_.back().t_s;
  // The random walk since the last measurement.
  if (updated_) {
    const double drift =
        voltage_compensated_ ? config_.compensated_drift_per_sqrt_s : config_.drift_per_sqrt_s;
    variance_ += drift * drift * std::max(0.0, t_s - last_update_s_);
  }
  last_update_s_ = t_s;
  updated_ = true;
  const double y = accel + pa::kGravity_mps2 + load;  // = k * thrust
  const double r = config_.accel_sigma_mps2 * config_.accel_sigma_mps2;
  const double s = thrust * thrust * variance_ + r;
  const double innovation = y - gain_ * thrust;
  if (!std::isfinite(innovation) || innovation * innovation > config_.gate_sigmas * config_.gate_sigmas * s) {
    ++rejected_;
    return;
  }
  const double k = variance_ * thrust / s;
  gain_ = std::clamp(gain_ + k * innovation, config_.min_gain, config_.max_gain);
  variance_ = (1.0 - k * thrust) * variance_;
  ++measurements_;
}

}  // namespace gs::estimation
