#include "groundstation/estimation/rate_response.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gs::estimation {

namespace {

constexpr double kStep_s = 0.001;            // the firmware's tick
constexpr double kTelemetryRate_Hz = 200.0;  // TELEMETRY_RATES
constexpr double kChiSquare1_95 = 3.84;

struct Candidate {
  double time_constant_s;
  double inertia_gain;
  double round_trip_s;
  double error;
};

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

// The firmware's loop on both axes replayed in model time (the ground's clock less the way up):
// a command acts from when it was sent, a telemetry sample shows the rate round_trip_s before it
// arrived.
double RateResponseIdentifier::squared_error(const std::vector<RateCommandSample>& commands,
                                             const std::vector<RateTelemetrySample>& telemetry,
                                             double equalised_time_constant_s, double time_constant_s,
                                             double inertia_gain, double round_trip_s) const {
  if (commands.empty() || telemetry.empty()) return std::numeric_limits<double>::infinity();
  const double ratio = equalised_time_constant_s / loop_.design_time_constant_s;
  const double lowpass = kStep_s / loop_.design_time_constant_s;
  const double motor = 1.0 - std::exp(-kStep_s / time_constant_s);
  Eigen::Array2d rate = telemetry.front().rate_radps.array();
  Eigen::Array2d integral = Eigen::Array2d::Zero(), equaliser = Eigen::Array2d::Zero(),
                 delivered = Eigen::Array2d::Zero();
  const Eigen::Array2d kp = loop_.kp_per_s.array(), ki = loop_.ki_per_s2.array(),
                       limit = loop_.integrator_limit_radps2.array();
  std::size_t c = 0;
  Eigen::Array2d setpoint = Eigen::Array2d::Zero();
  double t = commands.front().t_s;
  double error = 0.0;
  for (const RateTelemetrySample& sample : telemetry) {
    const double seen_at = sample.t_s - round_trip_s;
    while (t + kStep_s <= seen_at) {
      while (c < commands.size() && commands[c].t_s <= t) {
        setpoint =
            commands[c].rate_radps.array().cwiseMax(-loop_.rate_limit_radps).cwiseMin(loop_.rate_limit_radps);
        ++c;
      }
      const Eigen::Array2d e = setpoint - rate;
      integral = (integral + ki * e * kStep_s).cwiseMax(-limit).cwiseMin(limit);
      const Eigen::Array2d request = kp * e + integral;
      equaliser += lowpass * (request - equaliser);
      delivered += motor * (ratio * request + (1.0 - ratio) * equaliser - delivered);
      rate += inertia_gain * delivered * kStep_s;
      t += kStep_s;
    }
    if (seen_at < commands.front().t_s) continue;  // before the replay starts
    error += (sample.rate_radps.array() - rate).matrix().squaredNorm();
  }
  return error;
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
  // Coarse: the whole box in steps of 5 ms, 0.1 and 5 ms; then twice finer, each around the last.
  const Candidate centre{0.5 * (settings_.min_time_constant_s + settings_.max_time_constant_s),
                         0.5 * (settings_.min_inertia_gain + settings_.max_inertia_gain),
                         0.5 * settings_.max_round_trip_s, 0.0};
  const int half_tau =
      static_cast<int>(std::ceil((centre.time_constant_s - settings_.min_time_constant_s) / 0.005));
  const int half_gain = static_cast<int>(std::ceil((centre.inertia_gain - settings_.min_inertia_gain) / 0.1));
  const int half_trip = static_cast<int>(std::ceil(centre.round_trip_s / 0.005));
  Candidate best = search(centre, 0.005, 0.1, 0.005, half_tau, half_gain, half_trip);
  best = search(best, 0.0025, 0.05, 0.0025, 2, 2, 2);
  best = search(best, 0.0005, 0.01, 0.0005, 3, 3, 3);

  const int n = 2 * static_cast<int>(telemetry.size());
  const double variance = best.error / std::max(1, n - 3);
  // The profile over tau: at each lag the best (g, D) near the optimum's.
  const double threshold = best.error + kChiSquare1_95 * variance;
  const auto profile_edge = [&](double direction) {
    double edge = best.time_constant_s;
    Candidate at = best;
    for (double tau = best.time_constant_s + direction * 0.0005;
         tau >= settings_.min_time_constant_s && tau <= settings_.max_time_constant_s;
         tau += direction * 0.0005) {
      at.time_constant_s = tau;
      Candidate local{tau, 0.0, 0.0, std::numeric_limits<double>::infinity()};
      for (int j = -1; j <= 1; ++j)
        for (int k = -1; k <= 1; ++k) {
          const double gain = at.inertia_gain + j * 0.01, trip = std::max(0.0, at.round_trip_s + k * 0.0005);
          const double e = error_of(tau, gain, trip);
          if (e < local.error) local = Candidate{tau, gain, trip, e};
        }
      at = local;
      if (local.error > threshold) return edge;
      edge = tau;
    }
    return edge;
  };
  MotorIdentification id;
  id.time_constant_s = best.time_constant_s;
  id.time_constant_low_s = profile_edge(-1.0);
  id.time_constant_high_s = profile_edge(1.0);
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
