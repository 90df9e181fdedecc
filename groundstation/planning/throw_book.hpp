// The throws the ground station can fly, planned off the frame's path: the Fig. 5 throw with its
// TV-LQR (planned once, at construction, tens of milliseconds of IPOPT), and throws to target
// catch points (target_throw.hpp, up to ~70 ms each, the planner made on the first request).
#pragma once

#include <optional>

#include <Eigen/Core>

#include "groundstation/model/vehicle_limits.hpp"
#include "groundstation/planning/target_throw.hpp"
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

class ThrowBook {
 public:
  // Plans the Fig. 5 throw within `limits` and designs its TV-LQR with `weights`. Throws
  // std::runtime_error when either fails (the message says which).
  ThrowBook(const model::VehicleLimits& limits, const ThrowTrackingWeights& weights);

  const ThrowProblem& problem() const { return problem_; }
  const ThrowPlan& plan() const { return plan_; }
  const ThrowTracker& tracker() const { return tracker_; }

  // A throw from `origin_m` whose pole comes down on `target_m` (its lower end at the optimal
  // catching instant), aimed `miss_m` (along, across, up in the throw's direction) the other way
  // from the target, as throws to targets came down that far from theirs. nullopt when it cannot
  // be planned or tracked.
  std::optional<TargetThrow> plan_to(const Eigen::Vector3d& origin_m, const Eigen::Vector3d& target_m,
                                     const Eigen::Vector3d& miss_m);

 private:
  ThrowTrackingWeights weights_;
  ThrowProblem problem_;
  ThrowPlan plan_;
  ThrowTracker tracker_;
  std::optional<TargetThrowPlanner> target_planner_;
};

}  // namespace gs::planning
