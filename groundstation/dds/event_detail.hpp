// The details of the events (pa_msgs' Event on rt/pa/events) that a program reads back, written
// and read here only: an attempt's (ATTEMPT: its number and the throw's origin, where the ground
// station flies the thrower to wait for the pole), whether the thrower waits for it
// (POLE_WANTED) and a task change's (TASK_CHANGE, for people). `hil run`'s person
// hands the pole up from the first two. Pure functions.
#pragma once

#include <optional>
#include <string>

#include <Eigen/Core>

#include "groundstation/mission/vehicle_sequencer.hpp"

namespace gs::dds {

// "attempt 3, pole at 0.000 0.000 2.000" (metres, arena frame).
std::string attempt_event_detail(int number, const Eigen::Vector3d& origin_m);
// The origin in such a detail; none for any other text.
std::optional<Eigen::Vector3d> attempt_event_origin(const std::string& detail);

// "waiting" or "not waiting" (event_pole_wanted).
std::string pole_wanted_detail(bool waiting);
// Whether such a detail says waiting; none for any other text.
std::optional<bool> pole_wanted(const std::string& detail);

// "retreat -> hover (clear_of_pole)"; with `why` (a failed command's answer, MissionEvent::why)
// "arming -> parked (arm_failed): ARM refused: imu_unhealthy".
std::string task_change_detail(mission::Task from, mission::Task to, mission::Reason reason,
                               const std::string& why = {});

}  // namespace gs::dds
