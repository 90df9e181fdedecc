// The end of an attempt (Section VI): this throw's optimal catch (42) evaluated over the pole's
// recorded free flight, the launch state the throw flew against its plan's, the attempt's record
// in its throw's frame, and what the learner (adaptation/learner.hpp) takes of it: a Fig. 5 throw
// adapts the catch (its evaluation gated against the in-flight prediction) and is learnt from; a
// throw to a target teaches only its miss and is kept, neither adapted nor stored. Time and state
// are passed in (attempt_close_test.cpp).
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "groundstation/adaptation/learner.hpp"
#include "groundstation/control/throw_frame.hpp"
#include "groundstation/estimation/state_estimator.hpp"
#include "groundstation/planning/throw_book.hpp"
#include "groundstation/planning/throw_trajectory.hpp"
#include "groundstation/runtime/attempt.hpp"
#include "groundstation/runtime/task_control.hpp"

namespace gs::runtime {

// What the runtime kept of the attempt's throw and flight.
struct AttemptFlight {
  const planning::ThrowTrajectory* plan = nullptr;                       // the throw flown
  const planning::TargetThrow* target_throw = nullptr;                   // set for a throw to a target
  control::ThrowFrame frame;                                             // the attempt's throw frame
  std::optional<ThrowEnd> throw_end;                                     // the throw's last tracked state
  const std::vector<adaptation::TimedPoleState>* pole_flight = nullptr;  // launch to impact
  model::PoleParams pole_model;
  Eigen::Vector2d catch_target_xy_m = Eigen::Vector2d::Zero();  // the catch manoeuvre's last target
};

// The pole's free flight as the evaluation of (42) takes it: each new free-flight estimate from
// the launch until the impact, in time order (an estimate no newer than the last is skipped).
void record_free_flight(std::vector<adaptation::TimedPoleState>& flight, const estimation::PoleEstimate& pole,
                        const AttemptReport& report);

// Fills the report's evaluation and launch, and gives the learner the throw at `now_s`.
void close_attempt(const AttemptRequest& request, AttemptReport& report, const AttemptFlight& flight,
                   double now_s, adaptation::Learner& learner);

}  // namespace gs::runtime
