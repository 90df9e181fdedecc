// The condition word of one vehicle (vehicle_sequencer.hpp's bits), from what the runtime
// knows of it at a motion-capture frame: the link's view, the estimate, the pole, the task's
// and the attempt's clocks, the planner's verdicts and the operator's requests. A pure function
// of plain facts, so that every bit's rule is tested on its own (condition_word_test.cpp).
#pragma once

#include <cstdint>
#include <optional>

#include <Eigen/Core>

#include "groundstation/mission/vehicle_sequencer.hpp"

namespace gs::mission {

struct ConditionFacts {
  std::uint32_t requests = 0;  // the request bits held for the vehicle
  // The link works both ways: we hear the vehicle, and it hears our (signed) heartbeats, which
  // it needs before it accepts an ARM.
  bool link_up = false;
  bool armed = false;
  bool on_ground = false;  // disarmed, landed or killed
  bool command_failed = false;
  Task task = Task::parked;
  double in_task_s = 0.0;
  // The vehicle's estimate: none before the observer is initialised.
  bool estimated = false;
  double since_pose_s = 0.0;  // since its latest motion-capture pose
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_mps = Eigen::Vector3d::Zero();
  Eigen::Vector3d target_m = Eigen::Vector3d::Zero();     // where the task wants the centre of gravity
  Eigen::Vector3d set_point_m = Eigen::Vector3d::Zero();  // the carrot its law flies about now
  // How close counts as at the target, in place of the thresholds' at_target_m: a pass's thrower
  // at its throw's origin (runtime::AttemptThresholds::thrower_at_origin_m).
  std::optional<double> at_target_within_m;
  // The pole: the latest pose's end nearest this vehicle's plate, from the plate (set while the
  // vehicle holds the pole: throwing, rebalance, balance); the estimator's mode call.
  std::optional<double> pole_end_from_plate_m;
  bool pole_estimated_on_self = false;
  bool pole_estimated_free = false;
  double pole_tilt_rad = 0.0;
  bool pole_on_floor = false;  // in an attempt's flight, the pole's centre seen below the floor height
  double throw_duration_s = 0.0;
  // Set for the catcher of a running attempt only.
  bool catcher = false;
  bool catch_due = false, catch_unreachable = false, catch_infeasible = false, catch_missed = false;
  std::optional<double> balanced_for_s;  // the pole held upright in balance this long
};

struct ConditionThresholds {
  double lost_estimate_s = 0.3;
  double at_height_margin_m = 0.1;
  double at_target_m = 0.05;
  double at_target_speed_mps = 0.1;
  double pole_at_plate_m = 0.08;
  double upright_rad = 0.5;
  // Beyond this a pole on the plate has fallen (vehicle_sequencer.hpp): measured on the arena
  // envelope, a catcher still balancing a pole at 0.6-0.7 rad tilted itself over.
  double fallen_rad = 0.6;
  // A balancing vehicle this far from its set point is chasing a pole it cannot hold: the pole
  // has fallen as surely. Measured on the envelope: a catcher chased a pole leaning 20-35 degrees
  // for 3.6 m at 38 degrees of tilt, reaching 5 m/s; balancing that recovered over-energetic
  // catches ran up to 2.1 m (at 1 m, 12 of 300 such catches were let go).
  double runaway_m = 3.0;
  double release_low_s = 0.3;
  double balance_settle_s = 2.0;
  double balanced_hold_s = 1.0;
  double clear_settle_s = 1.0;
};

std::uint32_t condition_word(const ConditionFacts& facts, const ConditionThresholds& thresholds);

}  // namespace gs::mission
