// One vehicle of the act as the ground-station runtime keeps it: its mission sequencer and what
// is requested of it (the operator, the attempt), its task's law state, its mission commands and
// its adaptation. The runtime owns both; the attempt (attempt_runner.hpp) steers their requests
// and targets.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "groundstation/link/mission_commands.hpp"
#include "groundstation/mission/vehicle_sequencer.hpp"
#include "groundstation/runtime/task_control.hpp"
#include "groundstation/runtime/vehicle_adaptation.hpp"
#include "pa/vehicle_id.hpp"

namespace gs::runtime {

struct ActVehicle {
  ActVehicle(pa::VehicleId vehicle, const VehicleAdaptationSettings& settings)
      : id(vehicle), adaptation(vehicle, settings) {}
  pa::VehicleId id;
  mission::VehicleSequencer sequencer;
  TaskState laws;                  // target, carrot, integral, take-off ramp
  std::uint32_t requests = 0;      // mission::condition::request_* bits
  link::MissionCommands commands;  // ARM, DISARM, LAND, EXPECT_CATCH, CATCH_HANDLED
  std::string command_failure;     // why the last mission command failed ("ARM refused: killed")
  double last_pose_s = -1e9;
  VehicleAdaptation adaptation;  // thrust gain, motors, pose noise, on-board tilt
};

using ActVehicles = std::array<ActVehicle, 2>;  // by pa::act_slot()

}  // namespace gs::runtime
