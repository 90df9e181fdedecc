#include "groundstation/estimation/rate_response.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace gs::estimation {

namespace {

constexpr double kStep_s = 0.001;            // the firmware's tick
constexpr double kTelemetryRate_Hz = 200.0;  // TELEMETRY_RATES

// The firmware's loop on both axes replayed in model time (the ground's clock less the way up):
// a command acts from when it was sent, a telemetry sample shows the rate round_trip_s before it
// arrived.
struct Replay {
  double squared_error = std::numeric_limits<double>::infinity();
  double lag_product = 0.0;  // sum of each residual times the one before it (per axis)
};
// Stops once the squared error reaches stop_at (see squared_error()).
Replay replay(const RateLoopConfig& loop, const std::vector<RateCommandSample>& commands,
              const std::vector<RateTelemetrySample>& telemetry, double equalised_time_constant_s,
              double time_constant_s, double inertia_gain, double round_trip_s, double inertia_scale,
              double stop_at = std::numeric_limits<double>::infinity()) {
  Replay out;
  if (commands.empty() || telemetry.empty()) return out;
  const double ratio = equalised_time_constant_s / loop.design_time_constant_s;
  const double lowpass = kStep_s / loop.design_time_constant_s;
  const double motor = 1.0 - std::exp(-kStep_s / time_constant_s);
  Eigen::Array2d rate = telemetry.front().rate_radps.array();
  Eigen::Array2d integral = Eigen::Array2d::Zero(), equaliser = Eigen::Array2d::Zero(),
                 delivered = Eigen::Array2d::Zero(), motor_command = Eigen::Array2d::Zero(),
                 last_residual = Eigen::Array2d::Zero();
  const Eigen::Array2d kp = loop.kp_per_s.array(), ki = loop.ki_per_s2.array(),
                       limit = loop.integrator_limit_radps2.array();
  std::size_t c = 0;
  Eigen::Array2d setpoint = Eigen::Array2d::Zero();
  double t = commands.front().t_s;
  out.squared_error = 0.0;
  for (const RateTelemetrySample& sample : telemetry) {
    const double seen_at = sample.t_s - round_trip_s;
    while (t + kStep_s <= seen_at) {
      while (c < commands.size() && commands[c].t_s <= t) {
        setpoint =
            commands[c].rate_radps.array().cwiseMax(-loop.rate_limit_radps).cwiseMin(loop.rate_limit_radps);
        ++c;
      }
      const Eigen::Array2d e = setpoint - rate;
      integral = (integral + ki * e * kStep_s).cwiseMax(-limit).cwiseMin(limit);
      // The firmware's command from this sample drives the motors from the next (its tick).
      delivered += motor * (motor_command - delivered);
      // The loop's torque is J_file s (kp e + I), the vehicle's J_true turns it: g s (kp e + I).
      rate += inertia_gain * inertia_scale * delivered * kStep_s;
      const Eigen::Array2d request = kp * e + integral;
      equaliser += lowpass * (request - equaliser);
      motor_command = ratio * request + (1.0 - ratio) * equaliser;
      t += kStep_s;
    }
    if (seen_at < commands.front().t_s) continue;  // before the replay starts
    const Eigen::Array2d residual = sample.rate_radps.array() - rate;
    out.squared_error += residual.matrix().squaredNorm();
    out.lag_product += (residual * last_residual).sum();
    last_residual = residual;
    if (out.squared_error >= stop_at) return out;
  }
  return out;
}

}  // namespace

std::string_view refusal_name(IdentificationRefusal refusal) {
  switch (refusal) {
    case IdentificationRefusal::none: return "none";
    case IdentificationRefusal::no_telemetry: return "no_telemetry";
    case IdentificationRefusal::saturated: return "saturated";
    case IdentificationRefusal::no_motion: return "no_motion";
    case IdentificationRefusal::at_search_edge: return "at_search_edge";
    case IdentificationRefusal::not_confident: return "not_confident";
  }
  return "unknown";
}

RateResponseIdentifier::RateResponseIdentifier(const RateLoopConfig& loop,
                                               const RateResponseSettings& settings)
    : loop_(loop), settings_(settings) {}

double RateResponseIdentifier::excitation_duration_s() const {
  return 2.0 * (2.0 * settings_.half_period_s + settings_.rest_s);
}

Eigen::Vector2d RateResponseIdentifier::excitation(double elapsed_s) const {
  const double axis_s = 2.0 * settings_.half_period_s + settings_.rest_s;
  Eigen::Vector2d rate = Eigen::Vector2d::Zero();
  if (!(elapsed_s >= 0.0) || elapsed_s >= 2.0 * axis_s) return rate;
  const int axis = elapsed_s < axis_s ? 0 : 1;
  const double t = elapsed_s - axis * axis_s;
  if (t < settings_.half_period_s) rate[axis] = settings_.amplitude_radps;
  else if (t < 2.0 * settings_.half_period_s) rate[axis] = -settings_.amplitude_radps;
  return rate;
}

double RateResponseIdentifier::squared_error(const std::vector<RateCommandSample>& commands,
                                             const std::vector<RateTelemetrySample>& telemetry,
                                             double equalised_time_constant_s, double time_constant_s,
                                             double inertia_gain, double round_trip_s, double inertia_scale,
                                             double stop_at) const {
  return replay(loop_, commands, telemetry, equalised_time_constant_s, time_constant_s, inertia_gain,
                round_trip_s, inertia_scale, stop_at)
      .squared_error;
}

IdentificationResult RateResponseIdentifier::fit(const std::vector<RateCommandSample>& commands,
                                                 const std::vector<RateTelemetrySample>& telemetry,
                                                 double equalised_time_constant_s,
                                                 double inertia_scale) const {
  RateResponseFit fit(*this, commands, telemetry, equalised_time_constant_s, inertia_scale);
  while (!fit.advance(std::numeric_limits<int>::max())) {
  }
  return *fit.result();
}

RateResponseFit::RateResponseFit(const RateResponseIdentifier& identifier,
                                 std::vector<RateCommandSample> commands,
                                 std::vector<RateTelemetrySample> telemetry, double equalised_time_constant_s,
                                 double inertia_scale)
    : identifier_(identifier),
      commands_(std::move(commands)),
      telemetry_(std::move(telemetry)),
      equalised_s_(equalised_time_constant_s),
      inertia_scale_(inertia_scale) {
  const RateResponseSettings& settings = identifier_.settings();
  const double expected = identifier_.excitation_duration_s() * kTelemetryRate_Hz;
  IdentificationResult refused;
  if (commands_.empty() ||
      static_cast<double>(telemetry_.size()) < settings.min_telemetry_fraction * expected) {
    refused.refusal = IdentificationRefusal::no_telemetry;
    result_ = refused;
    return;
  }
  double peak = 0.0;
  for (const RateTelemetrySample& s : telemetry_) {
    if (s.saturated) {
      refused.refusal = IdentificationRefusal::saturated;
      result_ = refused;
      return;
    }
    peak = std::max(peak, s.rate_radps.cwiseAbs().maxCoeff());
  }
  if (peak < settings.min_response_fraction * settings.amplitude_radps) {
    refused.refusal = IdentificationRefusal::no_motion;
    result_ = refused;
    return;
  }
  // Coarse: the whole box in steps of 10 ms, 0.2 and 10 ms.
  const Eigen::Vector3d centre(0.5 * (settings.min_time_constant_s + settings.max_time_constant_s),
                               0.5 * (settings.min_inertia_gain + settings.max_inertia_gain),
                               0.5 * settings.max_round_trip_s);
  const Eigen::Vector3d step(0.01, 0.2, 0.01);
  const Eigen::Vector3i half(
      (centre - Eigen::Vector3d(settings.min_time_constant_s, settings.min_inertia_gain, 0.0))
          .cwiseQuotient(step)
          .array()
          .ceil()
          .cast<int>());
  queue_grid(centre, step, half);
}

void RateResponseFit::queue_grid(const Eigen::Vector3d& around, const Eigen::Vector3d& step,
                                 const Eigen::Vector3i& half) {
  const RateResponseSettings& settings = identifier_.settings();
  queue_.clear();
  next_ = 0;
  for (int i = -half[0]; i <= half[0]; ++i)
    for (int j = -half[1]; j <= half[1]; ++j)
      for (int k = -half[2]; k <= half[2]; ++k) {
        const Eigen::Vector3d c = around + Eigen::Vector3d(i * step[0], j * step[1], k * step[2]);
        if (c[0] < settings.min_time_constant_s - 1e-9 || c[0] > settings.max_time_constant_s + 1e-9 ||
            c[1] < settings.min_inertia_gain - 1e-9 || c[1] > settings.max_inertia_gain + 1e-9 ||
            c[2] < -1e-9 || c[2] > settings.max_round_trip_s + 1e-9)
          continue;
        queue_.push_back(c);
      }
}

bool RateResponseFit::advance(int replays) {
  while (!result_) {
    if (next_ < queue_.size()) {
      if (replays-- <= 0) return false;
      const Eigen::Vector3d& c = queue_[next_++];
      // Only a candidate better than the best so far (or than its profile side's) counts: a replay
      // stops once it cannot be (most do, early: a third of the fit's time).
      const double stop_at = stage_ < kProfileStage ? best_error_
                                                    : std::max(c[0] < best_[0] ? profile_low_ : profile_high_,
                                                               profile_best_error_);
      const double e = identifier_.squared_error(commands_, telemetry_, equalised_s_, c[0], c[1], c[2],
                                                 inertia_scale_, stop_at);
      if (stage_ < kProfileStage) {
        if (e < best_error_) best_ = c, best_error_ = e;
      } else {
        // The profile's two sides: the best (g, D) near the optimum's at tau* - h, then tau* + h.
        double& side = c[0] < best_[0] ? profile_low_ : profile_high_;
        side = std::min(side, e);
        if (e < profile_best_error_) profile_best_ = c, profile_best_error_ = e;
      }
      continue;
    }
    if (stage_ == kProfileStage && profile_best_error_ < best_error_ && profile_moves_ < kMaxProfileMoves) {
      ++profile_moves_;
      best_ = profile_best_;
      best_error_ = profile_best_error_;
      profile_low_ = profile_high_ = profile_best_error_ = std::numeric_limits<double>::infinity();
      queue_profile();
      continue;
    }
    // The stage is over: the next one around the best, or the result.
    ++stage_;
    if (stage_ == 1) queue_grid(best_, Eigen::Vector3d(0.005, 0.1, 0.005), Eigen::Vector3i(1, 1, 1));
    else if (stage_ == 2) queue_grid(best_, Eigen::Vector3d(0.0025, 0.05, 0.0025), Eigen::Vector3i(2, 2, 2));
    else if (stage_ == 3) queue_grid(best_, Eigen::Vector3d(0.0005, 0.01, 0.0005), Eigen::Vector3i(3, 3, 3));
    else if (stage_ == kProfileStage) queue_profile();
    else finish();
  }
  return true;
}

void RateResponseFit::queue_profile() {
  queue_.clear();
  next_ = 0;
  for (const double side : {-kProfileStep_s, kProfileStep_s})
    for (int j = -1; j <= 1; ++j)
      for (int k = -1; k <= 1; ++k)
        queue_.emplace_back(best_[0] + side, best_[1] + j * 0.01, std::max(0.0, best_[2] + k * 0.0005));
}

void RateResponseFit::finish() {
  const RateResponseSettings& settings = identifier_.settings();
  IdentificationResult result;
  const int n = 2 * static_cast<int>(telemetry_.size());
  const double curvature =
      (profile_low_ + profile_high_ - 2.0 * best_error_) / (2.0 * kProfileStep_s * kProfileStep_s);
  // Var(tau) = sigma^2 / curvature for white residuals, times (1 + rho) / (1 - rho) for residuals
  // correlated from sample to sample with rho (what the model misses is slow, not white).
  const double lag_product = replay(identifier_.loop(), commands_, telemetry_, equalised_s_, best_[0],
                                    best_[1], best_[2], inertia_scale_)
                                 .lag_product;
  const double rho = std::clamp(lag_product / best_error_, 0.0, 0.95);
  const double variance = best_error_ / std::max(1, n - 3) * (1.0 + rho) / (1.0 - rho);
  const double half_width =
      curvature > 0.0 ? 1.96 * std::sqrt(variance / curvature) : std::numeric_limits<double>::infinity();
  MotorIdentification id;
  id.time_constant_s = best_[0];
  id.time_constant_low_s = best_[0] - half_width;
  id.time_constant_high_s = best_[0] + half_width;
  id.inertia_gain = best_[1];
  id.round_trip_s = best_[2];
  id.rms_radps = std::sqrt(best_error_ / std::max(1, n));
  id.samples = static_cast<int>(telemetry_.size());
  const double edge_margin_s = 0.002;
  if (id.time_constant_s < settings.min_time_constant_s + edge_margin_s ||
      id.time_constant_s > settings.max_time_constant_s - edge_margin_s ||
      id.rms_radps > settings.min_response_fraction * settings.amplitude_radps) {
    result.refusal = IdentificationRefusal::at_search_edge;
  } else if (id.time_constant_high_s - id.time_constant_low_s >
             settings.max_interval_fraction * id.time_constant_s) {
    result.refusal = IdentificationRefusal::not_confident;
  } else {
    result.identified = id;
  }
  result_ = result;
}

}  // namespace gs::estimation
