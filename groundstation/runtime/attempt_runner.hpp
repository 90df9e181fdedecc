// The attempt the runtime flies (Section VII-B), one at a time: its admission and, for a throw to
// a target, its plan (attempt_admission.hpp); where each vehicle is sent for it (the throw's
// origin, the waiting point above the catch point, the retreat); its phases (attempt_phases.hpp)
// as the vehicles' tasks and the estimator's pole move it on; the catch it coordinates
// (catch_coordinator.hpp); what it hands the task laws (the throw flown, the catch manoeuvre);
// and its end, the report and what the learner takes (attempt_close.hpp).
// It reads the runtime's estimator and steers the vehicles' requests and targets; time and the
// vehicles are passed in (attempt_runner_test.cpp).
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "groundstation/adaptation/catch_energy.hpp"
#include "groundstation/adaptation/identification_memory.hpp"
#include "groundstation/adaptation/learner.hpp"
#include "groundstation/control/throw_frame.hpp"
#include "groundstation/estimation/state_estimator.hpp"
#include "groundstation/planning/throw_book.hpp"
#include "groundstation/runtime/act_vehicle.hpp"
#include "groundstation/runtime/attempt.hpp"
#include "groundstation/runtime/attempt_admission.hpp"
#include "groundstation/runtime/attempt_phases.hpp"
#include "groundstation/runtime/catch_coordinator.hpp"
#include "groundstation/runtime/condition_facts.hpp"
#include "groundstation/runtime/ground_station_config.hpp"
#include "groundstation/runtime/task_control.hpp"
#include "groundstation/runtime/task_entry.hpp"

namespace gs::runtime {

// The admission's thrust settings (attempt_admission.hpp) from the runtime's configuration.
ThrustAdmission thrust_admission(const GroundStationConfig& config);

class AttemptRunner {
 public:
  // The references are the runtime's, and outlive the runner.
  AttemptRunner(const GroundStationConfig& config, const estimation::StateEstimator& estimator,
                adaptation::Learner& learner, planning::ThrowBook& throws,
                const adaptation::IdentificationMemory& identifications);
  AttemptRunner(const AttemptRunner&) = delete;  // it holds the runtime's pieces by reference
  AttemptRunner& operator=(const AttemptRunner&) = delete;

  // Starts an attempt; false (and nothing changes, refusal() says why) while one is running, for
  // a vehicle not of the act, when a throw to a target cannot be planned, when a vehicle's
  // thrust (`thrust_of`) leaves it short of its part, or when the throw would leave the arena's
  // volume. The thrower is sent to its throw's origin, the catcher asked to catch.
  bool request(const AttemptRequest& request, ActVehicles& vehicles,
               const std::function<VehicleThrust(pa::VehicleId)>& thrust_of);
  AttemptRefusal refusal_kind() const { return refusal_kind_; }
  const std::string& refusal() const { return refusal_; }  // in words, with the numbers

  // The pole's latest motion-capture pose.
  void pole_seen(const estimation::MocapPose& pose) { last_pole_pose_ = pose; }
  // A frame's step, after the estimator's update and before the vehicles' sequencers: the
  // phases, the catch's plan, re-plan and verdicts, the pole's flight recorded, and the end.
  void update(double now_s, ActVehicles& vehicles);
  // What the vehicles' condition facts read of the attempt.
  AttemptView view(double now_s) const;

  // A vehicle enters `task`: what its entry needs of the attempt (the retreat, the catch's target
  // and window; a catching task starts the catch manoeuvre) ...
  void entering(mission::Task task, double now_s, TaskEntryContext& context);
  // ... and what the attempt notes once it has entered, at `here_m` (`estimated`: the vehicle's
  // estimate exists).
  void entered(const ActVehicle& vehicle, bool estimated, double now_s, const Eigen::Vector3d& here_m);
  // The throw and catch the task laws fly, and what a law's command tells the attempt back.
  FlownThrow flown() const;
  void commanded(const TaskCommand& command, double now_s);

  // The catcher's waiting point for the next throw: above the catch point, at the height the z
  // manoeuvre starts from (eq. (49)).
  Eigen::Vector3d waiting_target() const;
  // Whether `vehicle` waits for the pole to be put on (GroundStation::waiting_for_pole).
  bool waiting_for_pole(const ActVehicle& vehicle) const;

  // Where and in which direction a vehicle throws (see GroundStationConfig::throw_yaw_rad).
  control::ThrowFrame throw_frame(pa::VehicleId thrower) const;
  // The catching height (lower pole end) expected for the next throw, arena frame.
  double catch_height() const;

  AttemptPhase phase() const { return phase_; }
  const std::vector<AttemptReport>& reports() const { return reports_; }  // oldest first
  const AttemptReport& current() const { return current_; }

 private:
  const adaptation::AdaptationState& adaptation() const { return learner_.state(); }
  // The vehicle's take-off identification and its retry were refused and none is kept for it
  // (AttemptFacts::motors_unidentified).
  bool motors_unidentified(const ActVehicle& vehicle) const;
  // The catch point (lower end, x y) expected for the next throw, arena frame (throw_geometry.hpp).
  Eigen::Vector2d waiting_xy() const;
  std::optional<Eigen::Vector3d> aimed_m() const;  // the target throw's aim, if the attempt has one
  // Where the thrower's centre of gravity hovers before the throw: the throw's origin.
  Eigen::Vector3d throw_origin_target() const;
  // Where the thrower retreats after the release: over the throw's origin, at the origin's height
  // or, in a pass (AttemptRequest::thrower_catches_next), at the waiting point's.
  Eigen::Vector3d retreat_target() const;
  // The throw the attempt flies: the one planned to its target, else the Fig. 5 throw.
  const planning::ThrowTrajectory& flown_throw() const;
  const planning::ThrowTracker& flown_tracker() const;
  AttemptFacts facts(double now_s, const ActVehicles& vehicles) const;
  CatchView catch_view(const ActVehicle& catcher) const;
  void measure_impact_energy(const ActVehicle& catcher);
  void end(double now_s, ActVehicles& vehicles);

  const GroundStationConfig& config_;
  const estimation::StateEstimator& estimator_;
  adaptation::Learner& learner_;
  planning::ThrowBook& throws_;
  const adaptation::IdentificationMemory& identifications_;
  adaptation::CatchEnergyCorrection catch_energy_;
  CatchCoordinator catch_;
  std::optional<estimation::MocapPose> last_pole_pose_;

  control::ThrowFrame frame_;  // its thrower's throw frame (the last attempt's when idle)
  AttemptPhase phase_ = AttemptPhase::idle;
  AttemptRequest request_;
  AttemptReport current_;
  std::vector<AttemptReport> reports_;
  int attempt_count_ = 0;
  AttemptRefusal refusal_kind_ = AttemptRefusal::none;  // why the last request() was refused
  std::string refusal_;
  std::optional<planning::TargetThrow> target_throw_;  // the attempt's, when it throws to a target
  std::optional<ThrowEnd> throw_end_;                  // the throw's last tracked state near its end
  std::vector<adaptation::TimedPoleState> flight_;     // the pole's, from the launch to the impact
  // The pole's resting end from the plate's centre as the throw started, in the plate's axes.
  Eigen::Vector3d resting_offset_m_ = Eigen::Vector3d::Zero();
  std::optional<double> balanced_since_s_;
  std::optional<double> balanced_on_catcher_s_;
};

}  // namespace gs::runtime
