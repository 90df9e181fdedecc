// One throw as the adaptation of Section VI sees it and as the history keeps it: the launch
// state, the catch that was planned (catching height, waiting point, the trajectory's final
// target), the predicted and the actual catch point, the optimal catching instant (42) evaluated
// after the throw, where the catching vehicle stood at the impact, the pole energy after the
// impact (41) and the outcome.
//
// All positions are inertial (z up, docs/architecture.md, "Conventions"); "xy" is the horizontal plane. Times of the
// catch are measured from the launch; time_s is the ground-station time of the launch as the
// caller passes it (the store never reads a clock).
#pragma once

#include <Eigen/Dense>
#include <optional>
#include <string>
#include <string_view>

#include "groundstation/planning/catching_instant.hpp"
#include "pa/vehicle_id.hpp"

namespace gs::adaptation {

// What became of a throw. The order is the store's; the names are the CLI's, the store's and
// those of the trials' records (hil/trials/attempt_result.hpp), whose referee judges on truth.
enum class ThrowOutcome {
  caught,                // caught and balanced again (the paper's throws 8 and 9)
  dropped,               // caught, then lost while balancing
  missed,                // the catch manoeuvre was flown to the end, the pole missed the plate
  offset_practice,       // the catch manoeuvre was flown with a deliberate horizontal offset, so the
                         // pole was not meant to be caught (the paper's throws 2-7)
  aborted_out_of_reach,  // the catch was abandoned: the catch point was too far away (throws 2, 7)
  aborted,               // the catch was abandoned for another reason (say which in the note)
  throw_only,            // no catch was attempted (the paper's throw 1)
};

inline constexpr ThrowOutcome kAllThrowOutcomes[] = {ThrowOutcome::caught,
                                                     ThrowOutcome::dropped,
                                                     ThrowOutcome::missed,
                                                     ThrowOutcome::offset_practice,
                                                     ThrowOutcome::aborted_out_of_reach,
                                                     ThrowOutcome::aborted,
                                                     ThrowOutcome::throw_only};

// "caught", "dropped", "missed", "offset_practice", "aborted_out_of_reach", "aborted",
// "throw_only".
std::string_view to_string(ThrowOutcome outcome);
std::optional<ThrowOutcome> parse_throw_outcome(std::string_view name);

// Whether the catching vehicle flew its catch manoeuvre to the end, so that it was at rest at its
// target when the pole arrived: only then does its position at that instant measure the catching
// bias of Section VI-B (aborted and throw-only attempts leave the vehicle elsewhere).
bool catcher_flew_to_target(ThrowOutcome outcome);

// A horizontal point the pole's lower end reaches t_s after the launch.
struct CatchPoint {
  Eigen::Vector2d xy_m = Eigen::Vector2d::Zero();
  double t_s = 0.0;
};

// The optimal catching instant (42) evaluated after the throw: when the lower end would have had
// to meet a vehicle at rest for the pole to swing up by itself, and where it was then.
struct OptimalCatch {
  double t_s = 0.0;       // after the launch
  double height_m = 0.0;  // z of the lower end: this throw's optimal catching height
  Eigen::Vector2d xy_m = Eigen::Vector2d::Zero();
};

struct ThrowRecord {
  double time_s = 0.0;  // ground-station time of the launch
  ThrowOutcome outcome = ThrowOutcome::throw_only;
  // The throwing vehicle: each learns its own throw (throw_learning.hpp). Absent in throws stored
  // before schema 3, which the learner takes as vehicle 1's (the only thrower before passes).
  std::optional<pa::VehicleId> thrower;

  // The throwing vehicle and the pole at the launch (the end state of the throw, Fig. 5), plus the
  // lateral position and velocity out of the throw plane, which the planar state cannot hold.
  planning::PlanarLaunchState launch;
  double launch_y_m = 0.0;
  double launch_vy_mps = 0.0;

  // The catch as planned with the adapted values in force at the throw.
  double catch_height_used_m = 0.0;
  Eigen::Vector2d waiting_xy_m = Eigen::Vector2d::Zero();  // where the catching vehicle waited
  // The final target of the catching trajectory: the predicted catch point shifted by the offset
  // bias (and by the deliberate offset of a practice run). Absent if no manoeuvre was started.
  std::optional<Eigen::Vector2d> target_xy_m;

  std::optional<CatchPoint> predicted;  // the last prediction before the impact (Section V)
  std::optional<CatchPoint> actual;     // the lower end crossing catch_height_used_m, measured
  std::optional<OptimalCatch> optimal;  // eq. (42) evaluated after the throw
  // The catching vehicle at the instant of the impact (or of the actual crossing).
  std::optional<Eigen::Vector2d> catcher_at_impact_xy_m;
  // The pole's energy right after the impact, relative to the contact point (41).
  std::optional<double> energy_after_impact_J;

  std::string note;  // free text
};

// An empty string if every present number is finite, else what is wrong ("launch.x_m is not
// finite").
std::string validate(const ThrowRecord& record);

// The catching bias of Section VI-B this throw measured: the catching vehicle's position at the
// impact minus the target it was commanded to (which already contains the bias shift in force and
// any practice offset, so the samples measure the vehicle's tracking offset itself). Present only
// if catcher_flew_to_target(outcome) and both positions were recorded.
std::optional<Eigen::Vector2d> offset_bias_sample(const ThrowRecord& record);

}  // namespace gs::adaptation
