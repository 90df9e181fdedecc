#include "groundstation/runtime/condition_facts.hpp"

#include <algorithm>

#include "groundstation/runtime/task_control.hpp"

namespace gs::runtime {

double pole_end_from_plate_m(const estimation::MocapPose& pose, const Eigen::Vector3d& plate_m,
                             double half_length_m) {
  const Eigen::Vector3d n = pose.q * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d a = pose.p_m + half_length_m * n, b = pose.p_m - half_length_m * n;
  return std::min((a - plate_m).norm(), (b - plate_m).norm());
}

mission::ConditionFacts condition_facts(const VehicleView& v, const link::VehicleLinkStatus& status,
                                        const estimation::StateEstimator& estimator,
                                        const AttemptView& attempt, double now_s) {
  using mission::Task;
  mission::ConditionFacts f;
  f.requests = v.requests;
  f.link_up = !status.lost && (status.flags & pa::proto::kFlagGroundHeartbeatOk) != 0;
  f.armed = status.armed;
  f.on_ground = status.mode == pa::proto::Mode::disarmed || status.mode == pa::proto::Mode::landed ||
                status.mode == pa::proto::Mode::killed;
  f.command_failed = v.command_failed;
  f.task = v.task;
  f.in_task_s = now_s - v.task_since_s;
  f.estimated = estimator.vehicle_initialised(v.id);
  f.since_pose_s = now_s - v.last_pose_s;
  f.target_m = v.target_m;
  f.set_point_m = v.set_point_m;
  if (f.estimated) {
    const estimation::VehicleEstimate e = estimator.vehicle(v.id);
    f.position_m = e.state.p_m;
    f.velocity_mps = e.state.v_mps;
  }
  const bool holding = f.task == Task::throwing || f.task == Task::rebalance || f.task == Task::balance;
  if (holding && attempt.pole_pose && f.estimated)
    f.pole_end_from_plate_m = pole_end_from_plate_m(*attempt.pole_pose, estimator.plate(v.id).p_m,
                                                    estimator.pole_model().half_length_m);
  const estimation::PoleEstimate pole = estimator.pole();
  if (pole.valid) {
    f.pole_estimated_on_self = estimator.mode() == estimation::on_vehicle_mode(v.id);
    if (f.pole_estimated_on_self) f.pole_tilt_rad = tilt_rad(pole.state);
    f.pole_estimated_free = estimator.mode() == estimation::PoleMode::free;
  }
  // The pole on the floor ends an attempt's flight (before the launch it may lie there waiting
  // to be put on the thrower).
  const bool in_flight = attempt.phase == AttemptPhase::flight || attempt.phase == AttemptPhase::balancing;
  f.pole_on_floor =
      in_flight && attempt.pole_seen_height_m && *attempt.pole_seen_height_m < attempt.pole_down_height_m;
  f.throw_duration_s = attempt.throw_duration_s;
  if (attempt.phase == AttemptPhase::preparing && v.id == attempt.thrower)
    f.at_target_within_m = attempt.thrower_at_origin_m;
  f.catcher = attempt.catch_it && v.id != attempt.thrower && attempt.phase != AttemptPhase::idle;
  f.catch_due =
      (attempt.phase == AttemptPhase::throwing || attempt.phase == AttemptPhase::flight) && attempt.catch_due;
  f.catch_unreachable = attempt.catch_unreachable;
  f.catch_infeasible = attempt.catch_infeasible;
  f.catch_missed = attempt.catch_missed;
  if (attempt.balanced_since_s) f.balanced_for_s = now_s - *attempt.balanced_since_s;
  return f;
}

}  // namespace gs::runtime
