// The entry actions of a vehicle's mission tasks: what changes once, as the sequencer enters a
// task (mission/vehicle_sequencer.hpp), in the vehicle's laws (target, carrot, integral, ramp),
// its held requests, and the command it is sent: ARM (or DISARM first, for a vehicle that
// landed), EXPECT_CATCH with the catch's window, CATCH_HANDLED, LAND. A pure function of the task
// and what the runtime knows as it enters it; the runtime sends the command and keeps the
// attempt's account (task_entry_test.cpp).
#pragma once

#include <cstdint>
#include <optional>

#include <Eigen/Core>

#include "groundstation/mission/vehicle_sequencer.hpp"
#include "groundstation/runtime/task_control.hpp"
#include "pa/protocol.hpp"

namespace gs::runtime {

struct TaskEntrySettings {
  double take_off_height_m = 1.0;       // GroundStationConfig::take_off_height_m
  double clear_distance_m = 1.0;        // GroundStationConfig::clear_distance_m
  double land_handover_height_m = 0.1;  // GroundStationConfig::land_handover_height_m
  // A catcher this close to where the pole comes down has no direction away from it: it clears
  // along +y (the throw frame's side).
  double clear_min_away_m = 0.1;
  // EXPECT_CATCH's window, as the firmware bounds it (fw::ImpactDetector): 0.1-10 s.
  double expect_catch_min_s = 0.1;
  double expect_catch_max_s = 10.0;
};

// What the runtime knows as the vehicle enters its task.
struct TaskEntryContext {
  mission::Reason reason = mission::Reason::none;  // the transition's
  // Its estimated position; the task's target before its estimate exists.
  Eigen::Vector3d here_m = Eigen::Vector3d::Zero();
  double vertical_speed_mps = 0.0;  // its estimated vertical speed; 0 before its estimate exists
  pa::proto::Mode vehicle_mode = pa::proto::Mode::disarmed;     // as the link last heard it
  Eigen::Vector3d retreat_target_m = Eigen::Vector3d::Zero();   // the throw's origin, for the thrower
  Eigen::Vector2d catch_target_xy_m = Eigen::Vector2d::Zero();  // where the pole comes down
  double catch_window_s = 0.0;   // catching: how long the impact may take from now
  bool identify_motors = false;  // GroundStationConfig::identify_motors
};

struct TaskEntryCommand {
  pa::proto::CommandCode code = pa::proto::CommandCode::arm;
  std::int32_t argument = 0;
};

struct TaskEntry {
  std::optional<TaskEntryCommand> command;  // to send now
  // Arming a vehicle that landed: the command is DISARM, and ARM follows once it is accepted.
  bool arm_after_disarm = false;
  bool start_identification = false;  // the motors' identification flight (airborne in hover)
};

// Enters `task`: the laws' integral and carrot velocity reset, the task's own changes to
// `laws` and `requests` (the request bits, mission::condition), and what to send.
TaskEntry enter_task(mission::Task task, TaskState& laws, std::uint32_t& requests,
                     const TaskEntryContext& context, const TaskEntrySettings& settings);

}  // namespace gs::runtime
