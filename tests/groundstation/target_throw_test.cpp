// The throw planned for a target (target_throw.hpp): 20 targets 2.5-4.5 m away all round, each
// planned with every constraint of (34) held, F_N = 0 at the release, and the catch point the
// ground station predicts from the launch state on the target.
#include "groundstation/planning/target_throw.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>

#include "throw_plan_checks.hpp"

namespace {

using gs::planning::TargetThrowPlan;
using gs::planning::TargetThrowPlanner;
namespace planar = gs::model::planar;

const TargetThrowPlanner& planner() {
  static const TargetThrowPlanner p;
  return p;
}

const Eigen::Vector3d kHover(0.4, -0.7, 2.0);

// Target i of 20: yaw in 18-degree steps, distances cycling through 2.5, 3.0, ..., 4.5 m, the
// height at the Fig. 5 catch's height with a cycle of +/- 0.2 m.
Eigen::Vector3d target(int i) {
  const double pi = std::acos(-1.0);
  const double yaw = i * pi / 10.0;
  const double distance = 2.5 + 0.5 * (i % 5);
  const double height = planner().seed_catch_point().y() + 0.2 * std::sin(0.9 * i);
  return kHover + Eigen::Vector3d(distance * std::cos(yaw), distance * std::sin(yaw), height);
}

}  // namespace

TEST_CASE("the Fig. 5 throw seeds the target throws", "[target_throw]") {
  REQUIRE(planner().valid());
  const Eigen::Vector2d seed = planner().seed_catch_point();
  std::printf("Fig. 5 catch point: %.3f m away, %.3f m above the hover point, %.3f s after the release\n",
              seed.x(), seed.y(), planner().seed_catching_instant().t_s);
  CHECK(seed.x() > 2.0);
  CHECK(seed.x() < 4.5);
}

TEST_CASE("throws to 20 targets all round land the catch point on the target", "[target_throw]") {
  REQUIRE(planner().valid());
  double worst_prediction = 0.0, worst_instant = 0.0;
  for (int i = 0; i < 20; ++i) {
    const Eigen::Vector3d goal = target(i);
    const TargetThrowPlan plan = planner().plan(kHover, goal);
    INFO("target " << i << ": " << plan.status);
    REQUIRE(plan.success);
    const gs::planning::ThrowTrajectory& traj = plan.plan.trajectory;
    // Every constraint of (34), the end free but F_N = 0 at the release: as the planner reports
    // it, and the dynamics and forces recomputed from the returned points.
    CHECK(plan.plan.max_violation <= 1e-6);
    CHECK(throw_checks::max_collocation_defect(traj) < 1e-6);
    CHECK(std::abs(traj.normal_force_per_mass_mps2.back()) <= 1e-6);
    const double min_fn =
        *std::min_element(traj.normal_force_per_mass_mps2.begin(), traj.normal_force_per_mass_mps2.end());
    CHECK(min_fn >= -1e-6);
    for (std::size_t j = 0; j < traj.state.size(); ++j) {
      CHECK(gs::model::planar_normal_force_per_mass_mps2<double>(traj.state[j], traj.input[j]) ==
            Approx(traj.normal_force_per_mass_mps2[j]).margin(1e-12));
      CHECK(traj.input[j](planar::kThrust) >= 1.0 - 1e-6);
      CHECK(traj.input[j](planar::kThrust) <= 20.0 + 1e-6);
      CHECK(std::abs(traj.input[j](planar::kPitchRate)) <= 10.0 + 1e-6);
    }
    CHECK(traj.state.front().cwiseAbs().maxCoeff() <= 1e-9);
    // The plane faces the target.
    const Eigen::Vector3d direction = plan.to_world(1.0, 0.0) - kHover;
    CHECK((goal - kHover).head<2>().normalized().dot(direction.head<2>()) == Approx(1.0));
    // The catch point the catch-point predictor sees from the launch state (catch_point_predictor),
    // at the target's height, and the optimal catching instant's lower end (catching_instant).
    REQUIRE(plan.prediction.found);
    const double prediction_error =
        std::hypot(plan.prediction.x_m - goal.x(), plan.prediction.y_m - goal.y());
    CHECK(prediction_error <= 0.05);
    CHECK(plan.catching_instant_error_m <= 0.05);
    // The catcher's time: the 3D model's first catching instant no earlier than the planner's bound.
    CHECK(plan.catching_instant.t_s >= gs::planning::ThrowCatchTarget{}.min_catch_time_s - 0.005);
    worst_prediction = std::max(worst_prediction, prediction_error);
    worst_instant = std::max(worst_instant, plan.catching_instant_error_m);
    const gs::model::PlanarState<double>& end = traj.state.back();
    std::printf(
        "target %2d: %.2f m at %5.1f deg: %d solve(s), %3d iterations, cost %.2f, launch (x %.2f z %.2f vx %.2f vz "
        "%.2f theta %.2f alpha %.2f alpha' %.2f a_q %.2f), t_c %.3f s, prediction error %.4f mm, instant error "
        "%.3f mm\n",
        i, (goal - kHover).head<2>().norm(), plan.yaw_rad * 180.0 / std::acos(-1.0), plan.solves,
        plan.planning_iterations, plan.plan.cost, end(planar::kX), end(planar::kZ), end(planar::kVx),
        end(planar::kVz), end(planar::kTheta), end(planar::kAlpha), end(planar::kAlphaDot),
        traj.input.back()(planar::kThrust), plan.catching_instant.t_s, 1e3 * prediction_error,
        1e3 * plan.catching_instant_error_m);
  }
  std::printf("worst catch-point error over the 20 targets: prediction %.4f mm, catching instant %.3f mm\n",
              1e3 * worst_prediction, 1e3 * worst_instant);
}

TEST_CASE("a target out of the throw's reach is refused, not planned", "[target_throw]") {
  REQUIRE(planner().valid());
  for (const Eigen::Vector3d& offset : {Eigen::Vector3d(1.0, 0.0, 0.5), Eigen::Vector3d(0.0, -7.0, 0.5),
                                        Eigen::Vector3d(3.0, 0.0, std::nan(""))}) {
    const TargetThrowPlan plan = planner().plan(kHover, kHover + offset);
    INFO(plan.status);
    CHECK_FALSE(plan.success);
    CHECK(plan.status.rfind("rejected", 0) == 0);
    CHECK(plan.solves == 0);
  }
}

TEST_CASE("a miss of the 3D catching instant moves the planar target and plans again", "[target_throw]") {
  // The planar flight's torque quadrature leaves the first plan to target 4 about a micrometre off
  // (printed above; the millimetres seen before were the 3D check judging (42) in the xz-plane,
  // model/impact.hpp); with a tolerance below that, the planner corrects it.
  gs::planning::TargetThrowOptions options;
  options.catch_point_tolerance_m = 2e-7;
  const TargetThrowPlanner strict(gs::planning::ThrowProblem{}, options);
  REQUIRE(strict.valid());
  const TargetThrowPlan first = planner().plan(kHover, target(4));
  REQUIRE(first.success);
  REQUIRE(first.catching_instant_error_m > 4e-7);
  const TargetThrowPlan corrected = strict.plan(kHover, target(4));
  INFO(corrected.status);
  REQUIRE(corrected.success);
  CHECK(corrected.solves >= 2);
  CHECK(corrected.catching_instant_error_m <= 2e-7);
  std::printf("target 4 with a 0.2 um tolerance: %d solves, %d iterations, catching instant %.5f mm off\n",
              corrected.solves, corrected.planning_iterations, 1e3 * corrected.catching_instant_error_m);
}
