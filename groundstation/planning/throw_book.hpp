// The throws the ground station can fly, planned off the frame's path: the Fig. 5 throw with its
// TV-LQR (planned once, at construction, tens of milliseconds of IPOPT, or handed in planned),
// and throws to target catch points (target_throw.hpp, up to ~70 ms each, the planner made on the
// first request).
#pragma once

#include <memory>
#include <optional>

#include <Eigen/Core>

#include "groundstation/model/vehicle_limits.hpp"
#include "groundstation/planning/target_throw.hpp"
#include "groundstation/planning/throw_correction.hpp"
#include "groundstation/planning/throw_planner.hpp"
#include "groundstation/planning/throw_problem.hpp"
#include "groundstation/planning/throw_tracking.hpp"

namespace gs::planning {

// A throw planned to a target, with its TV-LQR.
struct TargetThrow {
  Eigen::Vector3d target_m;  // asked for (arena frame)
  TargetThrowPlan plan;      // planned to the point aimed at
  ThrowTracker tracker;
};

// The Fig. 5 throw within `limits` and its TV-LQR with `weights`: a function of the two alone,
// so ground stations of one configuration can share it (a campaign plans it once for all its
// attempts instead of once each: a sixth of an attempt's time).
struct Fig5Throw {
  model::VehicleLimits limits;
  ThrowTrackingWeights weights;
  ThrowProblem problem;
  ThrowPlan plan;
  ThrowTracker tracker;
  EndShiftSensitivity end_shift_sensitivity;  // G of the learnt throw (throw_correction.hpp)
  bool planned_for(const model::VehicleLimits& l, const ThrowTrackingWeights& w) const {
    return limits == l && weights == w;
  }
};
// Throws std::runtime_error when the plan or the TV-LQR fails (the message says which).
std::shared_ptr<const Fig5Throw> plan_fig5_throw(const model::VehicleLimits& limits,
                                                 const ThrowTrackingWeights& weights);

class ThrowBook {
 public:
  // Plans the Fig. 5 throw (plan_fig5_throw), or takes `planned` when it was planned for the same
  // limits and weights. Throws std::runtime_error when planning fails.
  ThrowBook(const model::VehicleLimits& limits, const ThrowTrackingWeights& weights,
            std::shared_ptr<const Fig5Throw> planned = nullptr);

  const ThrowProblem& problem() const { return fig5_->problem; }
  const ThrowPlan& plan() const { return fig5_->plan; }
  const ThrowTracker& tracker() const { return fig5_->tracker; }
  const EndShiftSensitivity& end_shift_sensitivity() const { return fig5_->end_shift_sensitivity; }
  const std::shared_ptr<const Fig5Throw>& fig5() const { return fig5_; }

  // A throw from `origin_m` whose pole comes down on `target_m` (its lower end at the optimal
  // catching instant), aimed `miss_m` (along, across, up in the throw's direction) the other way
  // from the target, as throws to targets came down that far from theirs. nullopt when it cannot
  // be planned or tracked.
  std::optional<TargetThrow> plan_to(const Eigen::Vector3d& origin_m, const Eigen::Vector3d& target_m,
                                     const Eigen::Vector3d& miss_m);

 private:
  std::shared_ptr<const Fig5Throw> fig5_;
  std::optional<TargetThrowPlanner> target_planner_;
};

}  // namespace gs::planning
