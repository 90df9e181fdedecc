#include "groundstation/planning/target_throw.hpp"

#include <cmath>
#include <exception>

#include "groundstation/model/impact.hpp"
#include "groundstation/model/planar_pole_flight.hpp"

namespace gs::planning {
namespace {

namespace planar = model::planar;

PlanarLaunchState launch_of(const ThrowPlan& plan) {
  const model::PlanarState<double>& s = plan.trajectory.state.back();
  return {s(planar::kX),  s(planar::kZ),     s(planar::kVx),
          s(planar::kVz), s(planar::kAlpha), s(planar::kAlphaDot)};
}

// The planar pole state (y = 0) turned by yaw about the vertical through the origin and moved
// there: the pole's flight is the same in any vertical plane (eq. (16)-(22) have no preferred
// horizontal direction).
model::PoleState to_world(const model::PoleState& planar_pole, double yaw_rad,
                          const Eigen::Vector3d& origin_m) {
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  model::PoleState world;
  world.p_m = origin_m + turn * planar_pole.p_m;
  world.v_mps = turn * planar_pole.v_mps;
  world.n = turn * planar_pole.n;
  world.omega_radps = turn * planar_pole.omega_radps;
  return world;
}

// A throw stretched along x by `scale` and raised by a ramp to `rise` at T (not a solution, a
// starting point whose shape is an optimal throw's).
ThrowTrajectory stretched(const ThrowTrajectory& trajectory, double scale, double rise_m) {
  ThrowTrajectory out = trajectory;
  const double duration = trajectory.duration_s();
  for (std::size_t i = 0; i < out.state.size(); ++i) {
    model::PlanarState<double>& s = out.state[i];
    s(planar::kX) *= scale;
    s(planar::kVx) *= scale;
    s(planar::kZ) += rise_m * out.t_s[i] / duration;
    s(planar::kVz) += rise_m / duration;
  }
  return out;
}

}  // namespace

Eigen::Vector3d TargetThrowPlan::to_world(double x_m, double z_m) const {
  return origin_m + Eigen::Vector3d(x_m * std::cos(yaw_rad), x_m * std::sin(yaw_rad), z_m);
}

TargetThrowPlanner::TargetThrowPlanner(const ThrowProblem& base, const TargetThrowOptions& options)
    : base_(base), options_(options) {
  base_.catch_target.reset();
  pole_.half_length_m = base_.params.pole_half_length_m;
  pole_.gravity_mps2 = base_.params.gravity_mps2;
  seed_ = plan_throw(base_, options_.solver);
  if (!seed_.success) return;
  const model::PlanarState<double>& end = seed_.trajectory.state.back();
  seed_catch_ =
      find_catching_instant(pole_state_at_launch(launch_of(seed_), pole_), pole_, options_.catching_instant);
  if (!seed_catch_.found) return;
  seed_catch_point_ = Eigen::Vector2d(seed_catch_.catch_point_m.x(), seed_catch_.catch_height_m);
  // The lower end's tilt at the catch against the tilt the planar flight carries on continuously
  // from the release: a multiple of pi (see ThrowCatchTarget::base_offset_rad).
  const model::PlanarFlightState<double> flown =
      model::planar_pole_flight<double>(model::planar_pole_at_launch<double>(end, pole_), seed_catch_.t_s,
                                        ThrowCatchTarget{}.flight_steps, pole_);
  const Eigen::Vector3d up = model::with_lower_end_as_base(seed_catch_.pole).n;
  const double pi = std::acos(-1.0);
  seed_base_offset_rad_ =
      pi * std::round((std::atan2(up.x(), up.z()) - flown(model::planar_flight::kAlpha)) / pi);
  // The reference: the target throw to Fig. 5's own catch point, from the Fig. 5 throw.
  reference_point_ = seed_catch_point_;
  reference_ =
      solve(Eigen::Vector3d::Zero(), Eigen::Vector3d(reference_point_.x(), 0.0, reference_point_.y()),
            {seed_.trajectory, seed_catch_.t_s});
}

TargetThrowPlan TargetThrowPlanner::plan(const Eigen::Vector3d& hover_m,
                                         const Eigen::Vector3d& target_m) const {
  if (!valid()) {
    TargetThrowPlan out;
    out.origin_m = hover_m;
    out.target_m = target_m;
    out.status = "rejected: the seed throws did not plan (" + seed_.status + "; " + reference_.status + ")";
    return out;
  }
  const Eigen::Vector3d delta = target_m - hover_m;
  const double distance = delta.head<2>().norm();
  return solve(hover_m, target_m,
               {stretched(reference_.plan.trajectory, distance / reference_point_.x(),
                          delta.z() - reference_point_.y()),
                reference_.plan.catch_time_s});
}

TargetThrowPlan TargetThrowPlanner::solve(const Eigen::Vector3d& hover_m, const Eigen::Vector3d& target_m,
                                          ThrowWarmStart warm) const {
  TargetThrowPlan out;
  out.origin_m = hover_m;
  out.target_m = target_m;
  const Eigen::Vector3d delta = target_m - hover_m;
  const double distance = delta.head<2>().norm();
  if (!delta.allFinite() || !hover_m.allFinite() || !(distance >= options_.min_distance_m) ||
      !(distance <= options_.max_distance_m)) {
    out.status = "rejected: the target's horizontal distance " + std::to_string(distance) +
                 " m is outside [" + std::to_string(options_.min_distance_m) + ", " +
                 std::to_string(options_.max_distance_m) + "] m";
    return out;
  }
  out.yaw_rad = std::atan2(delta.y(), delta.x());
  const Eigen::Vector2d wanted(distance, delta.z());  // in the plane, relative to the hover point

  ThrowProblem problem = base_;
  ThrowCatchTarget target;
  target.distance_m = wanted.x();
  target.height_m = wanted.y();
  target.base_offset_rad = seed_base_offset_rad_;
  target.catch_time_guess_s = warm.catch_time_s;
  target.pole = pole_;
  try {
    for (int attempt = 0; attempt <= options_.max_corrections; ++attempt) {
      problem.catch_target = target;
      out.plan = plan_throw(problem, options_.solver, &warm);
      ++out.solves;
      out.planning_iterations += out.plan.iterations;
      if (!out.plan.success) {
        out.status = "throw not planned: " + out.plan.status;
        return out;
      }
      // The check with the 3D model, in the world.
      out.pole_at_launch = to_world(pole_state_at_launch(launch_of(out.plan), pole_), out.yaw_rad, hover_m);
      out.catching_instant = find_catching_instant(out.pole_at_launch, pole_, options_.catching_instant);
      out.prediction = predict_catch_point(out.pole_at_launch, target_m.z(), pole_, options_.predictor);
      if (!out.catching_instant.found || !out.prediction.found) {
        out.status = "the planned throw's pole reaches no catching instant";
        return out;
      }
      const Eigen::Vector3d caught(out.catching_instant.catch_point_m.x(),
                                   out.catching_instant.catch_point_m.y(),
                                   out.catching_instant.catch_height_m);
      out.catching_instant_error_m = (caught - target_m).norm();
      out.prediction_error_m =
          std::hypot(out.prediction.x_m - target_m.x(), out.prediction.y_m - target_m.y());
      if (out.catching_instant_error_m <= options_.catch_point_tolerance_m) {
        out.success = true;
        out.status = "planned";
        return out;
      }
      // Move the planar target by the miss, in the plane, and plan again from this throw.
      const Eigen::Vector3d miss = caught - target_m;
      target.distance_m -= miss.x() * std::cos(out.yaw_rad) + miss.y() * std::sin(out.yaw_rad);
      target.height_m -= miss.z();
      target.catch_time_guess_s = out.plan.catch_time_s;
      warm = {out.plan.trajectory, out.plan.catch_time_s};
    }
  } catch (const std::exception& e) {
    out.status = std::string("planner error: ") + e.what();
    return out;
  }
  out.status = "the catch point misses the target by " + std::to_string(out.catching_instant_error_m) +
               " m after " + std::to_string(options_.max_corrections) + " corrections";
  return out;
}

}  // namespace gs::planning
