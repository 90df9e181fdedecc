#include "groundstation/runtime/task_entry.hpp"

#include <algorithm>
#include <cmath>

namespace gs::runtime {

TaskEntry enter_task(mission::Task task, TaskState& laws, std::uint32_t& requests,
                     const TaskEntryContext& context, const TaskEntrySettings& settings) {
  namespace c = mission::condition;
  using mission::Task;
  using pa::proto::CommandCode;
  const Eigen::Vector3d& here = context.here_m;
  laws.integral.setZero();
  laws.set_point.velocity_mps.setZero();
  // Hold where the vehicle is now.
  const auto hold_here = [&] {
    laws.set_point.position_m = here;
    laws.set_point.valid = true;
  };
  TaskEntry entry;
  switch (task) {
    case Task::parked:
      // Down, it has nothing left to land: a land asked meanwhile must not end its next take-off.
      requests &= ~c::request_land;
      laws.set_point.valid = false;
      break;
    case Task::failsafe: laws.set_point.valid = false; break;
    case Task::arming:
      requests &= ~c::request_take_off;
      // A vehicle that landed (on command or in its failsafe) arms only from disarmed.
      entry.arm_after_disarm = context.vehicle_mode == pa::proto::Mode::landed;
      entry.command = TaskEntryCommand{entry.arm_after_disarm ? CommandCode::disarm : CommandCode::arm, 0};
      break;
    case Task::take_off:
      laws.take_off_ramp_mps2 = 0.0;
      laws.target_m = Eigen::Vector3d(here.x(), here.y(), settings.take_off_height_m);
      hold_here();
      break;
    case Task::hover:
      if (!laws.set_point.valid) hold_here();
      entry.start_identification = context.identify_motors && context.reason == mission::Reason::airborne;
      break;
    case Task::balance:
      if (!laws.set_point.valid) laws.set_point.position_m = here;
      laws.set_point.valid = true;
      break;
    case Task::throwing: requests &= ~c::request_throw; break;
    case Task::release: requests &= ~c::request_abort; break;
    case Task::retreat:
      laws.target_m = context.retreat_target_m;
      hold_here();
      break;
    case Task::wait: break;
    case Task::catching:
      // EXPECT_CATCH carries the window in milliseconds.
      entry.command = TaskEntryCommand{
          CommandCode::expect_catch,
          static_cast<std::int32_t>(
              std::clamp(context.catch_window_s, settings.expect_catch_min_s, settings.expect_catch_max_s) *
              1000.0)};
      break;
    case Task::rebalance:
      // The ground station flies the caught pole from here: end the firmware's own reaction.
      entry.command = TaskEntryCommand{CommandCode::catch_handled, 0};
      laws.target_m = here;
      hold_here();
      break;
    case Task::clear: {
      requests &= ~(c::request_abort | c::request_catch);
      // Sideways, away from where the pole comes down, at the same height.
      Eigen::Vector2d away = here.head<2>() - context.catch_target_xy_m;
      if (away.norm() < settings.clear_min_away_m) away = Eigen::Vector2d(0.0, 1.0);
      laws.target_m.head<2>() = here.head<2>() + settings.clear_distance_m * away.normalized();
      laws.target_m.z() = here.z();
      hold_here();
      break;
    }
    case Task::descend:
      // Straight down to the hand-over height; never up, for a vehicle already below it.
      requests &= ~c::request_land;
      laws.target_m =
          Eigen::Vector3d(here.x(), here.y(), std::min(here.z(), settings.land_handover_height_m));
      hold_here();
      break;
    case Task::landing:
      requests &= ~c::request_land;
      // The on-board descent starts from the speed motion capture measures (its own drifts).
      entry.command = TaskEntryCommand{
          CommandCode::land, static_cast<std::int32_t>(std::clamp(
                                 std::lround(1e3 * context.vertical_speed_mps),
                                 -long{pa::proto::kLandSpeedMax_mmps}, long{pa::proto::kLandSpeedMax_mmps}))};
      break;
  }
  return entry;
}

}  // namespace gs::runtime
