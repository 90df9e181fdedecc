// A throw planned for a target catch point (the paper's outlook, Section VIII: the launch state
// left free under the lift-off constraint, so that either vehicle can throw to the other
// wherever it hovers).
//
// Problem (34) with its cost, in the vertical plane through the thrower's hover point and the
// target (the planar model of Fig. 4 turned by the direction's yaw; the pole's flight, gravity and
// drag do not care about the yaw), with the end state free: the launch thrust is tied to the end
// state by F_N(s_T, u_T) = 0, and the pole's flight after the release must reach its optimal
// catching instant (42) with the lower end on the target (throw_problem.hpp,
// catch_target_residuals). The planner differentiates that condition through the pole's planar
// flight (planar_pole_flight.hpp), whose torque quadrature is the one approximation; the result
// is then checked with the 3D model the ground station flies by: find_catching_instant
// (catching_instant.hpp) from the planned launch state. Where they differ by more than the
// tolerance, the planar target is moved by the difference and the throw re-planned from the
// last solution (a fixed-point iteration that converges in one step when the two models agree
// to first order).
//
// Every solve starts from a reference throw planned once, in the constructor: the Fig. 5 throw,
// and from it the target throw to Fig. 5's own catch point. That reference, stretched along x to
// the target's distance and raised to its height, is close to each target's optimum, so a plan
// takes 5-8 IPOPT iterations for targets 2.5-4.5 m away, against 13-26 from the stretched Fig. 5
// throw, whose launch state is not free.
#pragma once

#include <Eigen/Core>
#include <string>

#include "groundstation/model/pole_free_flight.hpp"
#include "groundstation/planning/catch_point_predictor.hpp"
#include "groundstation/planning/catching_instant.hpp"
#include "groundstation/planning/throw_planner.hpp"
#include "groundstation/planning/throw_problem.hpp"

namespace gs::planning {

struct TargetThrowOptions {
  ThrowSolverOptions solver;
  // The 3D catching instant's catch point may miss the target by this much before the planar
  // target is corrected and the throw planned again, at most max_corrections times.
  double catch_point_tolerance_m = 0.005;
  int max_corrections = 3;
  // Horizontal distances the planner accepts (the span the acceptance asks of it).
  double min_distance_m = 2.0;
  double max_distance_m = 5.0;
  CatchingInstantOptions catching_instant;
  CatchPointPredictorOptions predictor;
};

struct TargetThrowPlan {
  bool success = false;  // planned, every constraint held, and the catch point within tolerance
  std::string status;
  ThrowPlan plan;        // the planar throw, relative to the hover point, +x towards the target
  double yaw_rad = 0.0;  // the plane's +x in the world: (cos, sin, 0)
  Eigen::Vector3d origin_m = Eigen::Vector3d::Zero();  // the hover point the throw starts from
  Eigen::Vector3d target_m = Eigen::Vector3d::Zero();
  int solves = 0;               // IPOPT solves (1 + corrections)
  int planning_iterations = 0;  // IPOPT iterations over all solves
  // From the planned launch state, in the world: the pole just after the release, its optimal
  // catching instant (3D model), and the catch-point prediction at the target's height.
  model::PoleState pole_at_launch;
  CatchingInstant catching_instant;
  CatchPointPrediction prediction;
  double catching_instant_error_m = 0.0;  // |catching instant's lower end - target|
  double prediction_error_m = 0.0;        // |predicted catch point at the target height - target|

  // A point of the planar plan in the world.
  Eigen::Vector3d to_world(double x_m, double z_m) const;
};

class TargetThrowPlanner {
 public:
  // `base`: the duration, cost, limits and model of every throw (its launch state is the Fig. 5
  // throw that seeds the solves). Plans that throw now; see valid().
  explicit TargetThrowPlanner(const ThrowProblem& base = {}, const TargetThrowOptions& options = {});

  bool valid() const { return seed_.success && seed_catch_.found && reference_.success; }
  const ThrowPlan& seed() const { return seed_; }
  const CatchingInstant& seed_catching_instant() const { return seed_catch_; }
  // Fig. 5's catching instant relative to its hover point: (distance, height).
  Eigen::Vector2d seed_catch_point() const { return seed_catch_point_; }
  // The target throw to that point (hover at the origin, yaw 0): every plan's starting point.
  const TargetThrowPlan& reference() const { return reference_; }

  // Never throws. hover_m: the thrower's hover point (the throw starts there at rest, pole
  // upright); target_m: the catch point (the pole's lower end at its optimal catching instant).
  TargetThrowPlan plan(const Eigen::Vector3d& hover_m, const Eigen::Vector3d& target_m) const;

 private:
  ThrowProblem base_;
  TargetThrowOptions options_;
  model::PoleParams pole_;
  ThrowPlan seed_;
  CatchingInstant seed_catch_;
  Eigen::Vector2d seed_catch_point_ = Eigen::Vector2d::Zero();
  double seed_base_offset_rad_ = 0.0;
  TargetThrowPlan reference_;
  Eigen::Vector2d reference_point_ = Eigen::Vector2d::Zero();

  TargetThrowPlan solve(const Eigen::Vector3d& hover_m, const Eigen::Vector3d& target_m,
                        ThrowWarmStart warm) const;
};

}  // namespace gs::planning
