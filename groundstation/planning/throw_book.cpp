#include "groundstation/planning/throw_book.hpp"

#include <cmath>
#include <stdexcept>

#include "groundstation/control/throw_frame.hpp"

namespace gs::planning {

std::shared_ptr<const Fig5Throw> plan_fig5_throw(const model::VehicleLimits& limits,
                                                 const ThrowTrackingWeights& weights) {
  ThrowProblem problem;
  problem.limits = limits;
  ThrowPlan plan = plan_throw(problem);
  if (!plan.success) throw std::runtime_error("the throw could not be planned: " + plan.status);
  ThrowTracker tracker(plan.trajectory, weights);
  if (!tracker.valid()) throw std::runtime_error("the throw's TV-LQR could not be designed");
  const EndShiftSensitivity sensitivity = end_shift_sensitivity(tracker);
  return std::make_shared<const Fig5Throw>(
      Fig5Throw{limits, weights, problem, std::move(plan), std::move(tracker), sensitivity});
}

ThrowBook::ThrowBook(const model::VehicleLimits& limits, const ThrowTrackingWeights& weights,
                     std::shared_ptr<const Fig5Throw> planned)
    : fig5_(planned && planned->planned_for(limits, weights) ? std::move(planned)
                                                             : plan_fig5_throw(limits, weights)) {}

std::optional<TargetThrow> ThrowBook::plan_to(const Eigen::Vector3d& origin_m,
                                              const Eigen::Vector3d& target_m,
                                              const Eigen::Vector3d& miss_m) {
  if (!target_planner_) target_planner_.emplace(fig5_->problem);
  if (!target_planner_->valid()) return std::nullopt;
  const Eigen::Vector2d towards = target_m.head<2>() - origin_m.head<2>();
  const control::ThrowFrame towards_target{origin_m, std::atan2(towards.y(), towards.x())};
  const Eigen::Vector3d aim = target_m - (towards_target.to_arena(miss_m) - origin_m);
  TargetThrowPlan plan = target_planner_->plan(origin_m, aim);
  if (!plan.success) return std::nullopt;
  ThrowTracker tracker(plan.plan.trajectory, fig5_->weights);
  if (!tracker.valid()) return std::nullopt;
  return TargetThrow{target_m, std::move(plan), std::move(tracker)};
}

}  // namespace gs::planning
