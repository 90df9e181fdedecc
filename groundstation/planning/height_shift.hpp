// A smooth shift of the catch's end height, added to the catch manoeuvre's z reference while it
// is flown (runtime/catch_coordinator.hpp retimes the catch to this flight's (42)).
//
// Why. A throw in other air or from another vehicle meets (42) up to a metre above or below the
// learnt catching height, and that is known only some 0.1-0.4 s after the launch, when the catcher
// is already in its dive (the z manoeuvre starts ~0.9 s before the impact). Rebuilding the
// manoeuvre at the new height moved the whole z reference at once: the hover gains then chased a
// step without feed-forward and the plate met the pole 0.2-0.3 m short of a 0.8 m move (first 300
// envelope attempts, `hil campaign --attempts 300 --plant hil/config/envelope.yaml`). So the
// manoeuvre keeps its height and this shift carries the difference: each retarget plans a quintic
// from the shift's own position, rate and acceleration at that instant to the new target at rest
// at the manoeuvre's end, so the reference stays twice differentiable and its acceleration and
// jerk reach the feed-forward ((46), (47)). A move that would need more than `max_accel_mps2` is
// cut to the largest that does not: the plate then meets the pole where the thrust can take it.
//
// Pure: times are arguments (seconds, the runtime's clock).
#pragma once

#include "groundstation/planning/catch_trajectory.hpp"

namespace gs::planning {

struct HeightShiftSample {
  double z_m = 0.0, dz_mps = 0.0, ddz_mps2 = 0.0, jerk_mps3 = 0.0;
};

class HeightShift {
 public:
  // No shift: zero at all times.
  HeightShift() = default;

  // From the shift's state at `now_s` to `target_m` at rest at `end_s`. With less than
  // min_duration_s left it keeps its course (a last-moment move would be a step).
  void retarget(double now_s, double target_m, double end_s, double max_accel_mps2);

  // Before the latest retarget's instant: its state then; from the end on: at rest at the target.
  HeightShiftSample at(double t_s) const;
  double target_m() const { return target_m_; }

  static constexpr double min_duration_s = 0.05;

 private:
  // The quintic on [start_s_, end_s_], coefficients of (t - start_s_)^k.
  double c_[6] = {0, 0, 0, 0, 0, 0};
  double start_s_ = 0.0, end_s_ = 0.0;
  double target_m_ = 0.0;
};

// `reference` moved up by `shift`, its nominal inputs (46), (47) recomputed for the shifted
// acceleration and jerk.
CatchReference shifted(const CatchReference& reference, const HeightShiftSample& shift);

}  // namespace gs::planning
