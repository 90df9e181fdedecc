// An attempt as the runtime keeps it (Section VII-B): what the mission script asks for, its
// phases, and the ground station's own account of it (the referee in hil judges with the truth).
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

#include <Eigen/Core>

#include "groundstation/adaptation/throw_evaluation.hpp"
#include "groundstation/adaptation/throw_learning.hpp"
#include "groundstation/adaptation/throw_record.hpp"
#include "groundstation/control/throw_frame.hpp"
#include "groundstation/mission/vehicle_sequencer.hpp"
#include "pa/vehicle_id.hpp"

namespace gs::runtime {

// What the mission script (an operator, `hil fly`) asks for one attempt.
struct AttemptRequest {
  pa::VehicleId thrower = pa::kVehicle1;  // throws from its own throw frame (throw_frame())
  bool catch_it = true;                   // the other vehicle flies the catch
  Eigen::Vector2d catch_offset_m = Eigen::Vector2d::Zero();  // practice: catch this far off
  // Set: a throw to this catch point (x y, arena frame) instead of the Fig. 5 throw: planned for
  // this attempt (planning/target_throw.hpp, up to ~70 ms) from the thrower's throw origin, the
  // pole's lower end at its optimal catching instant on the point, at the adapted catching
  // height. The catcher waits above it. The planner is given the point moved against the mean miss
  // of the throws to targets before (adaptation::Learner::target_miss_m).
  std::optional<Eigen::Vector2d> target_xy_m;
  // A pass back and forth: the thrower catches the throw back. Three things shorten the pass
  // (docs/architecture.md, "A pass's cadence"): the thrower retreats to the height it will wait
  // at, above its throw's origin, rather than down to the origin (flown down and climbed back at
  // the carrot's 1 m/s, those 4 m were 8 s of a 15 s pass); it throws from within
  // AttemptThresholds::thrower_at_origin_m of its origin; and the catcher carries the pole down to
  // its own origin once it has balanced AttemptThresholds::pass_return_after_s.
  bool thrower_catches_next = false;
};

enum class AttemptPhase : std::uint8_t { idle, preparing, throwing, flight, balancing };

// What ended an attempt (the row of attempt_phases.hpp's table that took it to idle).
enum class AttemptEnd : std::uint8_t {
  none,                 // not ended
  catcher_lost,         // before the throw: the thrower keeps balancing the pole
  motors_unidentified,  // before the throw: a vehicle whose motors are not known flies no act
  throw_abandoned,      // aborted, or the pole fell, before the launch
  caught,               // balanced on the catcher for caught_after_s
  pole_down,
  timed_out,
};

// The ground station's own account of an attempt (the referee in hil judges with the truth).
struct AttemptReport {
  int number = 0;
  double throw_start_s = 0.0;
  std::optional<double> launch_s;                       // the estimator's launch
  std::optional<double> catch_start_s;                  // the z manoeuvre's start
  std::optional<double> impact_s;                       // the estimator's switch onto the catcher
  std::optional<Eigen::Vector3d> catcher_at_impact_m;   // its estimated position then
  std::optional<double> energy_after_impact_J;          // the pole's then (41), estimated
  mission::Reason catcher_end = mission::Reason::none;  // what ended the catch (caught, out_of_reach...)
  // what ended the throw (throw_ended, pole_left_early...)
  mission::Reason thrower_end = mission::Reason::none;
  AttemptEnd end = AttemptEnd::none;  // what ended the attempt
  Eigen::Vector2d waiting_xy_m = Eigen::Vector2d::Zero();
  Eigen::Vector2d last_target_xy_m = Eigen::Vector2d::Zero();
  std::optional<adaptation::CatchPoint> predicted;  // the latest catch-point prediction (lower end)
  // This throw's optimal catch (42) as predicted in flight (arena frame, time after the launch).
  std::optional<adaptation::OptimalCatch> predicted_optimal;
  double catch_height_m = 0.0;  // lower pole end, arena frame
  double travel_m = 0.0;        // the catcher's estimated path from its waiting point
  std::optional<adaptation::OptimalCatchEvaluation> optimal;  // (42) evaluated after the throw
  // The thrower's launch state as the last command of the throw estimated it (at tau within
  // launch_state_window_s of T), carried to T along the plan; and its error from the plan's.
  std::optional<planning::PlanarLaunchState> launch_flown;
  std::optional<adaptation::LaunchVector> launch_error;
  // The correction of the throw's end state this throw was flown with.
  adaptation::LaunchVector throw_correction = adaptation::LaunchVector::Zero();
  bool caught = false;  // balanced on the catcher
  // A throw to a target: the catch point asked for (lower end at the catching instant), and the
  // catch-point prediction when it had converged (CatchSettings::verdict_delay_s after the launch).
  std::optional<Eigen::Vector3d> target_m;
  std::optional<adaptation::CatchPoint> converged_prediction;
};

// What a vehicle entering `task` for `reason` at `now_s`, at `here_m`, tells the report: a
// rebalance is the impact (the first one, wherever the vehicle); the thrower's release in a
// running attempt says what ended the throw, and the catcher's clear, rebalance or hover after its
// catch started what ended the catch (each noted once).
void note_task_entry(const AttemptRequest& request, bool running, AttemptReport& report,
                     pa::VehicleId vehicle, mission::Task task, mission::Reason reason, double now_s,
                     const Eigen::Vector3d& here_m);

// How the attempt ended, as the adaptation classes throws (throw_record.hpp): a throw without a
// catch, caught, aborted (out of reach, or for any other reason of the catcher's), a practice
// catch off the catch point, dropped after an impact, or missed.
adaptation::ThrowOutcome outcome_of(const AttemptRequest& request, const AttemptReport& report);

// The attempt's record in its throw's frame, as the adaptation takes it (Section VI), at `now_s`
// when it never launched; `catch_target_xy_m` the catch manoeuvre's last target (arena frame).
// The learner adds the gated optimal catch.
adaptation::ThrowRecord record_of(const AttemptRequest& request, const AttemptReport& report,
                                  const control::ThrowFrame& frame, const Eigen::Vector2d& catch_target_xy_m,
                                  double now_s);

}  // namespace gs::runtime
