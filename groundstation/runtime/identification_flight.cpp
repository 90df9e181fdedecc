#include "groundstation/runtime/identification_flight.hpp"

#include <utility>

namespace gs::runtime {

void IdentificationFlight::start(double now_s, double equalised_s, double inertia_scale,
                                 double amplitude_scale) {
  estimation::RateResponseSettings settings = designed_.settings();
  // Judged by the same rates as the designed flight: the residual a fit leaves is the vehicle's
  // disturbances', which a smaller excitation does not shrink.
  settings.amplitude_radps *= amplitude_scale;
  settings.min_response_fraction /= amplitude_scale;
  identifier_ = estimation::RateResponseIdentifier(designed_.loop(), settings);
  start_s_ = now_s;
  equalised_s_ = equalised_s;
  inertia_scale_ = inertia_scale;
  fit_.reset();
  commands_.clear();
  telemetry_.clear();
  commands_.reserve(kMaxSamples);
  telemetry_.reserve(kMaxSamples);
}

void IdentificationFlight::stop() {
  start_s_.reset();
  fit_.reset();
  commands_.clear();
  telemetry_.clear();
}

Eigen::Vector2d IdentificationFlight::excitation(double now_s) const {
  return start_s_ ? identifier_.excitation(now_s - *start_s_) : Eigen::Vector2d::Zero();
}

void IdentificationFlight::command_sent(double now_s, const Eigen::Vector2d& rate_radps) {
  if (start_s_ && now_s >= *start_s_ && commands_.size() < kMaxSamples)
    commands_.push_back({now_s, rate_radps});
}

void IdentificationFlight::telemetry(double now_s, const Eigen::Vector2d& rate_radps, bool saturated) {
  if (recording(now_s) && telemetry_.size() < kMaxSamples)
    telemetry_.push_back({now_s, rate_radps, saturated});
}

void IdentificationFlight::telemetry(double now_s, const pa::proto::TelemetryRates& rates) {
  telemetry(now_s, Eigen::Vector2d(rates.rate_radps[0], rates.rate_radps[1]), (rates.saturation & 3u) != 0);
}

bool IdentificationFlight::recording(double now_s) const {
  return start_s_ && !fit_ && now_s >= *start_s_ &&
         now_s < *start_s_ + identifier_.excitation_duration_s() + kSettle_s;
}

std::optional<estimation::IdentificationResult> IdentificationFlight::finish(double now_s) {
  if (!start_s_ || now_s < *start_s_ + identifier_.excitation_duration_s() + kSettle_s) return std::nullopt;
  if (!fit_)
    fit_.emplace(identifier_, std::move(commands_), std::move(telemetry_), equalised_s_, inertia_scale_);
  if (!fit_->advance(kReplaysPerCall)) return std::nullopt;
  std::optional<estimation::IdentificationResult> result = fit_->result();
  stop();
  return result;
}

}  // namespace gs::runtime
