#include "groundstation/estimation/mode_selector.hpp"

#include <algorithm>
#include <cmath>

namespace gs::estimation {

ModeSelector::ModeSelector(const ModeSelectorParams& params) : params_(params) {}

void ModeSelector::reset(PoleMode active) {
  active_ = active;
  statistic_.fill(0.0);
}

std::optional<PoleMode> ModeSelector::step(
    const std::array<std::optional<double>, kPoleModeCount>& log_likelihood,
    const std::array<bool, kPoleModeCount>& favoured) {
  const std::optional<double>& active_ll = log_likelihood[mode_index(active_)];
  if (!active_ll || !std::isfinite(*active_ll)) return std::nullopt;
  std::optional<PoleMode> best;
  double best_margin = 0.0;
  for (PoleMode m : kPoleModes) {
    double& s = statistic_[mode_index(m)];
    const std::optional<double>& ll = log_likelihood[mode_index(m)];
    if (!pole_mode_transition_allowed(active_, m) || !ll || !std::isfinite(*ll)) {
      s = 0.0;
      continue;
    }
    const double cap = params_.max_increment_nats;
    s = std::max(0.0, s + std::clamp(*ll - *active_ll, -cap, cap));
    const double threshold =
        favoured[mode_index(m)] ? params_.favoured_threshold_nats : params_.switch_threshold_nats;
    if (s >= threshold && (!best || s - threshold > best_margin)) {
      best = m;
      best_margin = s - threshold;
    }
  }
  if (best) reset(*best);
  return best;
}

}  // namespace gs::estimation
