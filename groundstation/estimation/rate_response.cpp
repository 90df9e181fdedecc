#include "groundstation/estimation/rate_response.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gs::estimation {

namespace {

constexpr double kStep_s = 0.001;            // the firmware's tick
constexpr double kTelemetryRate_Hz = 200.0;  // TELEMETRY_RATES

struct Candidate {
  double time_constant_s;
  double inertia_gain;
  double round_trip_s;
  double error;
};

// The firmware's loop on both axes replayed in model time (the ground's clock less the way up):
// a command acts from when it was sent, a telemetry sample shows the rate round_trip_s before it
// arrived.
struct Replay {
  double squared_error = std::numeric_limits<double>::infinity();
  double lag_product = 0.0;  // sum of each residual times the one before it (per axis)
};
Replay replay(const RateLoopConfig& loop, const std::vector<RateCommandSample>& commands,
              const std::vector<RateTelemetrySample>& telemetry, double equalised_time_constant_s,
              double time_constant_s, double inertia_gain, double round_trip_s) {
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
      rate += inertia_gain * delivered * kStep_s;
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
                                             double inertia_gain, double round_trip_s) const {
  return replay(loop_, commands, telemetry, equalised_time_constant_s, time_constant_s, inertia_gain,
                round_trip_s)
      .squared_error;
}

IdentificationResult RateResponseIdentifier::fit(const std::vector<RateCommandSample>& commands,
                                                 const std::vector<RateTelemetrySample>& telemetry,
                                                 double equalised_time_constant_s) const {
  IdentificationResult result;
  const double expected = excitation_duration_s() * kTelemetryRate_Hz;
  if (commands.empty() ||
      static_cast<double>(telemetry.size()) < settings_.min_telemetry_fraction * expected) {
    result.refusal = IdentificationRefusal::no_telemetry;
    return result;
  }
  double peak = 0.0;
  for (const RateTelemetrySample& s : telemetry) {
    if (s.saturated) {
      result.refusal = IdentificationRefusal::saturated;
      return result;
    }
    peak = std::max(peak, s.rate_radps.cwiseAbs().maxCoeff());
  }
  if (peak < settings_.min_response_fraction * settings_.amplitude_radps) {
    result.refusal = IdentificationRefusal::no_motion;
    return result;
  }

  const auto error_of = [&](double tau, double gain, double trip) {
    return squared_error(commands, telemetry, equalised_time_constant_s, tau, gain, trip);
  };
  // The best of a grid of (tau, g, D) around `around`, `steps` either side of it.
  const auto search = [&](const Candidate& around, double d_tau, double d_gain, double d_trip, int steps_tau,
                          int steps_gain, int steps_trip) {
    Candidate best{0.0, 0.0, 0.0, std::numeric_limits<double>::infinity()};
    for (int i = -steps_tau; i <= steps_tau; ++i) {
      const double tau = around.time_constant_s + i * d_tau;
      if (tau < settings_.min_time_constant_s - 1e-9 || tau > settings_.max_time_constant_s + 1e-9) continue;
      for (int j = -steps_gain; j <= steps_gain; ++j) {
        const double gain = around.inertia_gain + j * d_gain;
        if (gain < settings_.min_inertia_gain - 1e-9 || gain > settings_.max_inertia_gain + 1e-9) continue;
        for (int k = -steps_trip; k <= steps_trip; ++k) {
          const double trip = around.round_trip_s + k * d_trip;
          if (trip < -1e-9 || trip > settings_.max_round_trip_s + 1e-9) continue;
          const double e = error_of(tau, gain, trip);
          if (e < best.error) best = Candidate{tau, gain, trip, e};
        }
      }
    }
    return best;
  };
  // Coarse: the whole box in steps of 10 ms, 0.2 and 10 ms; then finer, each around the last. A
  // grid twice as fine from the start found the same minima at four times the cost (~4400
  // replays, over a second in the HIL guest's emulation, where the ground station's lockstep
  // waits at most one); this costs ~1100.
  const Candidate centre{0.5 * (settings_.min_time_constant_s + settings_.max_time_constant_s),
                         0.5 * (settings_.min_inertia_gain + settings_.max_inertia_gain),
                         0.5 * settings_.max_round_trip_s, 0.0};
  const int half_tau =
      static_cast<int>(std::ceil((centre.time_constant_s - settings_.min_time_constant_s) / 0.01));
  const int half_gain = static_cast<int>(std::ceil((centre.inertia_gain - settings_.min_inertia_gain) / 0.2));
  const int half_trip = static_cast<int>(std::ceil(centre.round_trip_s / 0.01));
  Candidate best = search(centre, 0.01, 0.2, 0.01, half_tau, half_gain, half_trip);
  best = search(best, 0.005, 0.1, 0.005, 1, 1, 1);
  best = search(best, 0.0025, 0.05, 0.0025, 2, 2, 2);
  best = search(best, 0.0005, 0.01, 0.0005, 3, 3, 3);

  const int n = 2 * static_cast<int>(telemetry.size());
  // The profile's curvature over tau, each side re-minimised over (g, D) near the optimum's.
  const auto profile = [&](double tau) {
    double e = std::numeric_limits<double>::infinity();
    for (int j = -1; j <= 1; ++j)
      for (int k = -1; k <= 1; ++k)
        e = std::min(
            e, error_of(tau, best.inertia_gain + j * 0.01, std::max(0.0, best.round_trip_s + k * 0.0005)));
    return e;
  };
  const double h = 0.001;
  const double curvature =
      (profile(best.time_constant_s + h) + profile(best.time_constant_s - h) - 2.0 * best.error) /
      (2.0 * h * h);
  // Var(tau) = sigma^2 / curvature for white residuals, times (1 + rho) / (1 - rho) for residuals
  // correlated from sample to sample with rho (what the model misses is slow, not white).
  const double lag_product = replay(loop_, commands, telemetry, equalised_time_constant_s,
                                    best.time_constant_s, best.inertia_gain, best.round_trip_s)
                                 .lag_product;
  const double rho = std::clamp(lag_product / best.error, 0.0, 0.95);
  const double variance = best.error / std::max(1, n - 3) * (1.0 + rho) / (1.0 - rho);
  const double half_width =
      curvature > 0.0 ? 1.96 * std::sqrt(variance / curvature) : std::numeric_limits<double>::infinity();
  MotorIdentification id;
  id.time_constant_s = best.time_constant_s;
  id.time_constant_low_s = best.time_constant_s - half_width;
  id.time_constant_high_s = best.time_constant_s + half_width;
  id.inertia_gain = best.inertia_gain;
  id.round_trip_s = best.round_trip_s;
  id.rms_radps = std::sqrt(best.error / std::max(1, n));
  id.samples = static_cast<int>(telemetry.size());

  const double edge_margin_s = 0.002;
  if (best.time_constant_s < settings_.min_time_constant_s + edge_margin_s ||
      best.time_constant_s > settings_.max_time_constant_s - edge_margin_s ||
      id.rms_radps > settings_.min_response_fraction * settings_.amplitude_radps) {
    result.refusal = IdentificationRefusal::at_search_edge;
    return result;
  }
  if (id.time_constant_high_s - id.time_constant_low_s >
      settings_.max_interval_fraction * id.time_constant_s) {
    result.refusal = IdentificationRefusal::not_confident;
    return result;
  }
  result.identified = id;
  return result;
}

}  // namespace gs::estimation
