#include "groundstation/adaptation/adaptation_law.hpp"

#include <algorithm>
#include <cmath>

#include "groundstation/model/impact.hpp"
#include "groundstation/planning/catching_instant.hpp"

namespace gs::adaptation {

AdaptationSettings nominal_adaptation_settings(const model::PoleParams& params) {
  AdaptationSettings settings;
  const planning::CatchingInstant nominal = planning::find_catching_instant(
      planning::pole_state_at_launch(planning::fig5_launch_state(), params), params);
  if (nominal.found) {
    settings.nominal_catch_height_m = nominal.catch_height_m;
    settings.nominal_waiting_xy_m = nominal.catch_point_m;
  }
  settings.window = 0;
  settings.target_energy_J = model::upright_energy_J(params);
  return settings;
}

std::string validate(const AdaptationSettings& s) {
  if (!std::isfinite(s.nominal_catch_height_m)) return "the nominal catching height is not finite";
  if (!s.nominal_waiting_xy_m.allFinite()) return "the nominal waiting point is not finite";
  if (s.window < 0) return "the window must be 0 (plain mean) or a positive number of throws";
  if (!std::isfinite(s.target_energy_J) || !(s.target_energy_J > 0.0)) {
    return "the target energy E* must be positive";
  }
  return "";
}

AdaptationState initial_adaptation(const AdaptationSettings& settings) {
  AdaptationState state;
  state.catch_height_m = settings.nominal_catch_height_m;
  state.waiting_xy_m = settings.nominal_waiting_xy_m;
  return state;
}

double iterative_mean_gain(std::int64_t samples_taken, int window) {
  std::int64_t divisor = std::max<std::int64_t>(samples_taken, 0) + 1;
  if (window > 0) divisor = std::min<std::int64_t>(divisor, window);
  return 1.0 / static_cast<double>(divisor);
}

AdaptationState adapt(const AdaptationState& state, const ThrowRecord& record, int window) {
  AdaptationState next = state;
  if (record.optimal) {
    // VI-A: the catching height and the waiting point from the evaluated optimal instant (42).
    const double gain = iterative_mean_gain(state.catch_point_samples, window);
    next.catch_height_m += gain * (record.optimal->height_m - state.catch_height_m);
    next.waiting_xy_m += gain * (record.optimal->xy_m - state.waiting_xy_m);
    next.catch_point_samples = state.catch_point_samples + 1;
  }
  if (const std::optional<Eigen::Vector2d> sample = offset_bias_sample(record)) {
    // VI-B: the average catching bias of the past attempts.
    const double gain = iterative_mean_gain(state.bias_samples, window);
    next.offset_bias_m += gain * (*sample - state.offset_bias_m);
    next.bias_samples = state.bias_samples + 1;
  }
  return next;
}

AdaptationState recompute_adaptation(const AdaptationSettings& settings,
                                     std::span<const ThrowRecord> throws) {
  AdaptationState state = initial_adaptation(settings);
  for (const ThrowRecord& record : throws) state = adapt(state, record, settings.window);
  return state;
}

Eigen::Vector2d compensate_offset_bias(const Eigen::Vector2d& xy_m, const AdaptationState& state) {
  return xy_m - state.offset_bias_m;
}

}  // namespace gs::adaptation
