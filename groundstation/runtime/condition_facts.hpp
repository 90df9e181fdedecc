// The facts of one vehicle's condition word (mission/condition_word.hpp) at a motion-capture
// frame, gathered from where the runtime keeps them: the link's view of the vehicle, the
// estimator, the vehicle's own sequencer and requests, and the attempt. Time and state are passed
// in (condition_facts_test.cpp); the thresholds that turn facts into bits are the word's.
#pragma once

#include <cstdint>
#include <optional>

#include <Eigen/Core>

#include "groundstation/estimation/mocap_pose.hpp"
#include "groundstation/estimation/state_estimator.hpp"
#include "groundstation/link/ground_link.hpp"
#include "groundstation/mission/condition_word.hpp"
#include "groundstation/runtime/attempt.hpp"

namespace gs::runtime {

// One vehicle as the runtime tracks it.
struct VehicleView {
  pa::VehicleId id{pa::proto::kGroundNode};
  std::uint32_t requests = 0;
  bool command_failed = false;
  mission::Task task = mission::Task::parked;
  double task_since_s = 0.0;
  double last_pose_s = -1e9;  // its latest motion-capture pose's arrival
  Eigen::Vector3d target_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d set_point_m = Eigen::Vector3d::Zero();
};

// The attempt as the vehicles' conditions see it.
struct AttemptView {
  AttemptPhase phase = AttemptPhase::idle;
  pa::VehicleId thrower = pa::kVehicle1;
  bool catch_it = false;
  double throw_duration_s = 0.0;  // the flown throw's T
  // The catch coordinator's: due by the clock, and its verdicts.
  bool catch_due = false, catch_unreachable = false, catch_infeasible = false, catch_missed = false;
  std::optional<double> balanced_since_s;          // the pole settled on a balancing vehicle since
  std::optional<double> pole_seen_height_m;        // the pole's centre, last seen
  std::optional<estimation::MocapPose> pole_pose;  // the latest pose of the pole
  double pole_down_height_m = 0.25;                // AttemptThresholds::pole_down_height_m
  // A pass: the thrower preparing is at its throw's origin this close
  // (AttemptThresholds::thrower_at_origin_m).
  std::optional<double> thrower_at_origin_m;
};

mission::ConditionFacts condition_facts(const VehicleView& vehicle, const link::VehicleLinkStatus& link,
                                        const estimation::StateEstimator& estimator,
                                        const AttemptView& attempt, double now_s);

// The pole's end nearest the plate, from a pose of the pole.
double pole_end_from_plate_m(const estimation::MocapPose& pose, const Eigen::Vector3d& plate_m,
                             double half_length_m);

}  // namespace gs::runtime
