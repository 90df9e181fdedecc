#include "groundstation/mission/condition_word.hpp"

namespace gs::mission {

std::uint32_t condition_word(const ConditionFacts& f, const ConditionThresholds& t) {
  namespace c = condition;
  std::uint32_t w = f.requests;
  if (!f.link_up) w |= c::vehicle_lost;
  if (!f.estimated || f.since_pose_s > t.lost_estimate_s) w |= c::estimate_lost;
  if (f.armed) w |= c::armed;
  if (f.on_ground) w |= c::on_ground;
  if (f.command_failed) w |= c::command_failed;
  if (f.estimated) {
    if (f.position_m.z() >= f.target_m.z() - t.at_height_margin_m) w |= c::at_height;
    if ((f.position_m - f.target_m).norm() < f.at_target_within_m.value_or(t.at_target_m) &&
        f.velocity_mps.norm() < t.at_target_speed_mps)
      w |= c::at_target;
  }
  // While the vehicle holds the pole, the pole counts as on the plate as long as the latest
  // pose puts an end at the plate: a mode call on the innovations during the throw's fastest
  // phase or while a caught pole settles on the absorber can be wrong for a frame or two, and
  // leaving the pole on such a call drops it.
  if (f.pole_end_from_plate_m && *f.pole_end_from_plate_m < t.pole_at_plate_m) w |= c::pole_on_self;
  if (f.pole_estimated_on_self) {
    w |= c::pole_on_self;
    if (f.pole_tilt_rad < t.upright_rad) w |= c::pole_upright;
    if (f.pole_tilt_rad > t.fallen_rad) w |= c::pole_fallen;
    if (f.estimated && f.task == Task::balance && (f.position_m - f.set_point_m).norm() > t.runaway_m)
      w |= c::pole_fallen;
  }
  if (f.pole_estimated_free) w |= c::pole_free;
  if (f.pole_on_floor) w |= c::pole_down;
  if (f.task == Task::throwing && f.in_task_s >= f.throw_duration_s) w |= c::throw_over;
  if (f.task == Task::release && f.in_task_s >= t.release_low_s) w |= c::release_over;
  if (f.catcher) {
    if (f.catch_due) w |= c::catch_due;
    if (f.catch_unreachable) w |= c::catch_unreachable;
    if (f.catch_infeasible) w |= c::catch_infeasible;
    if (f.catch_missed) w |= c::catch_missed;
  }
  if (f.task == Task::balance && f.in_task_s >= t.balance_settle_s && f.balanced_for_s &&
      *f.balanced_for_s >= t.balanced_hold_s)
    w |= c::settled;
  if (f.task == Task::clear && f.in_task_s >= t.clear_settle_s) w |= c::settled;
  return w;
}

}  // namespace gs::mission
