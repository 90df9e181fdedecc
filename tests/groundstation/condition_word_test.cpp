// The condition word (groundstation/mission/condition_word.hpp): each bit's rule on its own,
// from a healthy vehicle hovering at its target, with the word printed by bit names.
#include <catch2/catch.hpp>

#include <cstdint>
#include <string>

#include "groundstation/mission/condition_word.hpp"

namespace {

using gs::mission::condition_names;
using gs::mission::condition_word;
using gs::mission::ConditionFacts;
using gs::mission::ConditionThresholds;
using gs::mission::Task;
namespace c = gs::mission::condition;

// Armed, heard both ways, estimated, at rest on its target at 1 m, no pole.
ConditionFacts hovering() {
  ConditionFacts f;
  f.link_up = true;
  f.armed = true;
  f.task = Task::hover;
  f.in_task_s = 5.0;
  f.estimated = true;
  f.since_pose_s = 0.005;
  f.position_m = Eigen::Vector3d(0.0, 0.0, 1.0);
  f.target_m = f.position_m;
  f.set_point_m = f.position_m;
  f.throw_duration_s = 2.5;
  return f;
}

// The bits `f` sets beyond the hovering vehicle's.
std::string added(const ConditionFacts& f, const ConditionThresholds& t = {}) {
  return condition_names(condition_word(f, t) & ~condition_word(hovering(), t));
}

}  // namespace

TEST_CASE("A healthy vehicle hovering at its target: armed, at height, at target") {
  CHECK(condition_names(condition_word(hovering(), {})) == "armed|at_height|at_target");
}

TEST_CASE("Requests pass through as they are held") {
  ConditionFacts f = hovering();
  f.requests = c::request_take_off | c::request_land;
  CHECK(added(f) == "request_take_off|request_land");
}

TEST_CASE("The link and the estimate: lost when either way fails or the poses stop") {
  ConditionFacts f = hovering();
  f.link_up = false;
  CHECK(added(f) == "vehicle_lost");
  const ConditionThresholds t;
  f = hovering();
  f.since_pose_s = t.lost_estimate_s;
  CHECK(added(f) == "0");  // only beyond the timeout
  f.since_pose_s = t.lost_estimate_s + 0.001;
  CHECK(added(f) == "estimate_lost");
  f = hovering();
  f.estimated = false;  // no estimate: lost, and neither at height nor at target
  CHECK(condition_names(condition_word(f, t)) == "estimate_lost|armed");
}

TEST_CASE("On the ground and a failed command are reported as the link says") {
  ConditionFacts f = hovering();
  f.on_ground = true;
  f.command_failed = true;
  CHECK(added(f) == "on_ground|command_failed");
}

TEST_CASE("At height from the margin below the target; at target within distance and speed") {
  const ConditionThresholds t;
  ConditionFacts f = hovering();
  f.position_m.z() = f.target_m.z() - t.at_height_margin_m - 0.001;
  CHECK(condition_names(condition_word(f, t)) == "armed");
  f.position_m.z() = f.target_m.z() - t.at_height_margin_m + 0.001;
  CHECK(condition_names(condition_word(f, t)) == "armed|at_height");  // 9.9 cm off: not at target
  f = hovering();
  f.position_m.x() += 0.9 * t.at_target_m;
  CHECK(condition_names(condition_word(f, t)) == "armed|at_height|at_target");
  f.velocity_mps.y() = t.at_target_speed_mps;  // at the speed bound: moving
  CHECK(condition_names(condition_word(f, t)) == "armed|at_height");
  // A wider distance in the facts (a pass's thrower at its origin) replaces the thresholds'.
  f = hovering();
  f.position_m.x() += 2.0 * t.at_target_m;
  CHECK(condition_names(condition_word(f, t)) == "armed|at_height");
  f.at_target_within_m = 3.0 * t.at_target_m;
  CHECK(condition_names(condition_word(f, t)) == "armed|at_height|at_target");
  f.velocity_mps.y() = t.at_target_speed_mps;  // the speed bound stays
  CHECK(condition_names(condition_word(f, t)) == "armed|at_height");
}

TEST_CASE("The pole on the plate: the estimator's call, or an end at the plate while holding") {
  const ConditionThresholds t;
  ConditionFacts f = hovering();
  f.pole_estimated_on_self = true;
  f.pole_tilt_rad = t.upright_rad - 0.01;
  CHECK(added(f) == "pole_on_self|pole_upright");
  f.pole_tilt_rad = t.upright_rad;
  CHECK(added(f) == "pole_on_self");
  f.pole_tilt_rad = t.fallen_rad;
  CHECK(added(f) == "pole_on_self");
  f.pole_tilt_rad = t.fallen_rad + 0.01;
  CHECK(added(f) == "pole_on_self|pole_fallen");
  // Balancing, a vehicle led away from its set point has lost the pole, however it leans.
  f.pole_tilt_rad = 0.3;
  f.task = Task::balance;
  f.set_point_m = f.position_m + Eigen::Vector3d(t.runaway_m, 0.0, 0.0);
  CHECK(added(f) == "pole_on_self|pole_upright");
  f.set_point_m.x() += 0.01;
  CHECK(added(f) == "pole_on_self|pole_upright|pole_fallen");
  f.task = Task::hover;  // another task flies no balance to run away with
  CHECK(added(f) == "pole_on_self|pole_upright");
  f = hovering();
  f.pole_end_from_plate_m = t.pole_at_plate_m - 0.001;  // the estimator calls it free: a flip
  f.pole_estimated_free = true;
  CHECK(added(f) == "pole_on_self|pole_free");
  f.pole_end_from_plate_m = t.pole_at_plate_m;
  CHECK(added(f) == "pole_free");
  f = hovering();
  f.pole_on_floor = true;
  CHECK(added(f) == "pole_down");
}

TEST_CASE("The throw and the release are over by the task's clock") {
  const ConditionThresholds t;
  ConditionFacts f = hovering();
  f.task = Task::throwing;
  f.in_task_s = f.throw_duration_s - 0.001;
  CHECK(added(f) == "0");
  f.in_task_s = f.throw_duration_s;
  CHECK(added(f) == "throw_over");
  f.task = Task::release;
  f.in_task_s = t.release_low_s - 0.001;
  CHECK(added(f) == "0");
  f.in_task_s = t.release_low_s;
  CHECK(added(f) == "release_over");
}

TEST_CASE("The catch's verdicts reach only the catcher of a running attempt") {
  ConditionFacts f = hovering();
  f.catch_due = f.catch_unreachable = f.catch_infeasible = f.catch_missed = true;
  CHECK(added(f) == "0");
  f.catcher = true;
  CHECK(added(f) == "catch_due|catch_unreachable|catch_infeasible|catch_missed");
}

TEST_CASE("Settled: balancing long enough with the pole still, or clear of an aborted catch") {
  const ConditionThresholds t;
  ConditionFacts f = hovering();
  f.task = Task::balance;
  f.in_task_s = t.balance_settle_s;
  CHECK(added(f) == "0");  // never still
  f.balanced_for_s = t.balanced_hold_s - 0.001;
  CHECK(added(f) == "0");
  f.balanced_for_s = t.balanced_hold_s;
  CHECK(added(f) == "settled");
  f.in_task_s = t.balance_settle_s - 0.001;  // still, but not balancing long enough
  CHECK(added(f) == "0");
  f = hovering();
  f.task = Task::clear;
  f.in_task_s = t.clear_settle_s - 0.001;
  CHECK(added(f) == "0");
  f.in_task_s = t.clear_settle_s;
  CHECK(added(f) == "settled");
}
