// The adaptation of Section VI: after each throw the catching height, the catching vehicle's
// waiting point and its offset bias are updated by iterative means, so systematic deviations of
// the real throws from the nominal one (Fig. 9) and of the catching vehicle from its commanded
// position stop costing travel distance and catch energy (Fig. 10).
//
// The iterative mean (VI-A: "an iterative mean scheme"; VI-B: "the average ... of all past
// attempts"): with k samples taken,
//   x_{k+1} = x_k + g_k (x_meas - x_k),   g_k = 1 / (k + 1),
// which is exactly the arithmetic mean of the samples; the nominal value only stands until the
// first sample replaces it (g_0 = 1). Optionally a window N >= 1 bounds the gain from below:
// g_k = 1 / min(k + 1, N). Up to N samples this is the mean; after that an exponential forgetting
// with weight 1/N (memory of about N throws), so slow drifts (battery, a worn shock absorber) are
// followed. window = 0 is the paper's plain mean and the default.
//
// What each throw contributes (see ThrowRecord):
// - catching height and waiting point: the lower end's height and horizontal position at the
//   optimal catching instant (42) evaluated after the throw. Both come from the same evaluated
//   point, so the adapted catch point is the mean optimal catch point. Every throw whose instant
//   could be evaluated counts, whatever became of the catch: the paper adapts during throw 1 (no
//   catch) and throws 2-7 (practice catches with a 1 m offset, 2 and 7 aborted), since the pole's
//   flight does not depend on the catcher.
// - offset bias: the catching vehicle's position at the impact minus its commanded target, only
//   when it flew the catch manoeuvre to the end (caught, dropped, missed, offset practice: at
//   rest at its target when the pole arrived). An aborted or throw-only attempt measures nothing
//   about where the vehicle comes to rest, so it leaves the bias alone. Relative to the commanded
//   target rather than to the predicted point, because the target already contains the shift in
//   force and the practice offset: the samples measure the vehicle's own error, and their mean
//   converges to it instead of to the residual of a partly corrected error.
// The whole catch trajectory is shifted by -bias (VI-B: the error is assumed independent of
// the position), so that the vehicle comes to rest where the prediction says.
#pragma once

#include <Eigen/Dense>
#include <cstdint>
#include <span>

#include "groundstation/adaptation/throw_record.hpp"
#include "groundstation/model/pole_free_flight.hpp"

namespace gs::adaptation {

struct AdaptationSettings {
  // The values in force before the first throw (after a reset): the nominal catch point.
  double nominal_catch_height_m = 0.0;
  Eigen::Vector2d nominal_waiting_xy_m = Eigen::Vector2d::Zero();
  // 0: the mean of all throws since the last reset (the paper). N >= 1: see the header.
  int window = 0;
  // E* = m_p g L (41), against which each throw's post-impact energy is compared.
  double target_energy_J = 0.0;
};

// The nominal settings: the catch point of the nominal throw (the Fig. 5 launch state flown
// freely to the optimal catching instant (42), planning/catching_instant.hpp), window 0 and
// E* of the given pole.
AdaptationSettings nominal_adaptation_settings(const model::PoleParams& params = {});

// An empty string if the settings are usable, else what is wrong.
std::string validate(const AdaptationSettings& settings);

struct AdaptationState {
  double catch_height_m = 0.0;
  Eigen::Vector2d waiting_xy_m = Eigen::Vector2d::Zero();
  std::int64_t catch_point_samples = 0;  // throws the height and waiting point rest on
  Eigen::Vector2d offset_bias_m = Eigen::Vector2d::Zero();
  std::int64_t bias_samples = 0;  // catches the bias rests on
  bool operator==(const AdaptationState&) const = default;
};

// The nominal values with no samples.
AdaptationState initial_adaptation(const AdaptationSettings& settings);

// g_k of the header for k samples taken.
double iterative_mean_gain(std::int64_t samples_taken, int window);

// The state after one more throw.
AdaptationState adapt(const AdaptationState& state, const ThrowRecord& record, int window);

// The state after the given throws in order, from initial_adaptation(settings). The store checks
// its persisted values against this.
AdaptationState recompute_adaptation(const AdaptationSettings& settings, std::span<const ThrowRecord> throws);

// A position of the catch trajectory (the waiting point, the target) shifted by the offset bias
// so that the vehicle, erring by the bias, comes to rest at `xy_m` (Section VI-B).
Eigen::Vector2d compensate_offset_bias(const Eigen::Vector2d& xy_m, const AdaptationState& state);

}  // namespace gs::adaptation
