// The attempt's phases (Section VII-B) as a table, in the shape of the vehicles' sequencer
// (mission/vehicle_sequencer.hpp): each frame the runtime turns what it knows of the attempt into
// a word of condition bits (attempt_conditions(), from plain facts); the constexpr table
// kAttemptTransitions lists, in order, "from any of these phases, when all of these bits hold and
// none of those, go to that phase (idle: the attempt ends) for this reason"; the first matching
// row wins.
//
// A frame runs the table twice, around the catch's work (catch_coordinator.hpp): once for the
// phases before the launch (preparing, throwing: at most one step), then, after the catch's
// prediction and re-planning, for the phases in flight (flight, balancing: steps until none
// applies, so that the catcher's balance and the end of the attempt can come in one frame).
// What a step does beyond the phase (the catch planned, the launch noted, the attempt closed and
// learnt from) is the runtime's. Tested row by row in attempt_phases_test.cpp.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "groundstation/mission/transition_table.hpp"
#include "groundstation/mission/vehicle_sequencer.hpp"
#include "groundstation/runtime/attempt.hpp"

namespace gs::runtime {

std::string_view phase_name(AttemptPhase phase);

using PhaseSet = std::uint32_t;
constexpr PhaseSet phase_bit(AttemptPhase p) { return PhaseSet{1} << static_cast<unsigned>(p); }
template <typename... P>
constexpr PhaseSet phases(P... p) {
  return (phase_bit(p) | ...);
}
inline constexpr PhaseSet kBeforeLaunch = phases(AttemptPhase::preparing, AttemptPhase::throwing);
inline constexpr PhaseSet kInFlight = phases(AttemptPhase::flight, AttemptPhase::balancing);

namespace attempt_condition {
inline constexpr std::uint32_t catcher_lost = 1u << 0;         // a catcher in its failsafe before any impact
inline constexpr std::uint32_t thrower_throwing = 1u << 1;     // the thrower's task is throwing
inline constexpr std::uint32_t thrower_releasing = 1u << 2;    // the thrower's task is release
inline constexpr std::uint32_t launched = 1u << 3;             // the estimator called the launch
inline constexpr std::uint32_t catcher_balancing = 1u << 4;    // the catcher's task is balance
inline constexpr std::uint32_t balanced_long = 1u << 5;        // for caught_after_s
inline constexpr std::uint32_t pole_down = 1u << 6;            // the pole seen on the floor
inline constexpr std::uint32_t timed_out = 1u << 7;            // attempt_timeout_s after the throw's start
inline constexpr std::uint32_t motors_unidentified = 1u << 8;  // see AttemptFacts
inline constexpr int kCount = 9;
}  // namespace attempt_condition
std::string_view attempt_condition_name(int bit);
// The bits of a word by name, "launched|pole_down", or "0".
std::string attempt_condition_names(std::uint32_t word);

std::string_view attempt_end_name(AttemptEnd end);

using AttemptTransition = mission::TableRow<AttemptPhase, AttemptEnd>;  // to idle: the attempt ends

namespace ac = attempt_condition;
inline constexpr std::array kAttemptTransitions = {
    // Before the throw, a lost catcher ends the attempt; once thrown, the pole comes down and ends it.
    AttemptTransition{phases(AttemptPhase::preparing), ac::catcher_lost, 0, AttemptPhase::idle,
                      AttemptEnd::catcher_lost},
    // Nor is a vehicle flown in the act with motors it could not identify: the pole is not handed
    // up (or stays with the thrower).
    AttemptTransition{phases(AttemptPhase::preparing), ac::motors_unidentified, 0, AttemptPhase::idle,
                      AttemptEnd::motors_unidentified},
    AttemptTransition{phases(AttemptPhase::preparing), ac::thrower_throwing, 0, AttemptPhase::throwing,
                      AttemptEnd::none},
    // The launch: the estimator's call to free flight at the throw's end.
    AttemptTransition{phases(AttemptPhase::throwing), ac::launched, 0, AttemptPhase::flight,
                      AttemptEnd::none},
    AttemptTransition{phases(AttemptPhase::throwing), 0, ac::thrower_throwing | ac::thrower_releasing,
                      AttemptPhase::idle, AttemptEnd::throw_abandoned},
    // In flight: caught, the catcher balancing, the pole down, or time up.
    AttemptTransition{kInFlight, ac::catcher_balancing | ac::balanced_long, 0, AttemptPhase::idle,
                      AttemptEnd::caught},
    AttemptTransition{phases(AttemptPhase::flight), ac::catcher_balancing, 0, AttemptPhase::balancing,
                      AttemptEnd::none},
    AttemptTransition{kInFlight, ac::pole_down, 0, AttemptPhase::idle, AttemptEnd::pole_down},
    AttemptTransition{kInFlight, ac::timed_out, 0, AttemptPhase::idle, AttemptEnd::timed_out},
};

// The first row of kAttemptTransitions that matches `phase` under `conditions`, or nullptr.
const AttemptTransition* find_attempt_transition(AttemptPhase phase, std::uint32_t conditions);

// The rows the table takes one after another under one word, until none applies (the phases in
// flight): `phase` moved along, and the last row taken (nullptr: none).
const AttemptTransition* settle_attempt(AttemptPhase& phase, std::uint32_t conditions);

// What the runtime knows of the attempt at a frame.
struct AttemptFacts {
  bool catch_it = true;
  mission::Task thrower_task = mission::Task::hover;
  mission::Task catcher_task = mission::Task::hover;
  bool impact = false;             // the report has an impact
  bool catcher_end_noted = false;  // the report already says what ended the catch
  double now_s = 0.0;
  double throw_start_s = 0.0;     // the report's
  double throw_duration_s = 0.0;  // the flown throw's T
  // The estimator's last switch to free flight, if its last switch is one.
  std::optional<double> free_flight_call_s;
  std::optional<double> catcher_balancing_since_s;  // the runtime's clock of it
  std::optional<double> pole_seen_height_m;         // the pole's centre, last seen
  // The thrower, or a catcher the attempt has, ended its take-off's identification refused, the
  // retry too, and no accepted identification is kept for it: its equaliser flies the airframe
  // file's lag unconfirmed. A 70 ms thrower so balanced at 30 ms, dropped the pole, and the
  // disturbance made its attitude diverge until the firmware stopped it (hil campaign
  // --attempts 49 --seed 1 --plant hil/config/envelope/motors_60ms.yaml --replay 14).
  bool motors_unidentified = false;
};

struct AttemptThresholds {
  // Only a call to free flight this close to the throw's end is its launch: during the throw's
  // fastest phase the mode call can flip for a frame (see the conditions' pole at the plate).
  double launch_call_window_s = 0.05;
  // The pole balanced on the catcher this long: caught. An attempt ends this long after its
  // throw started whatever happens (a pole lost from sight, a catcher hovering on).
  double caught_after_s = 3.0;
  double attempt_timeout_s = 15.0;
  double pole_down_height_m = 0.25;  // the pole's centre below this: it lies on the floor
  // In a pass (AttemptRequest::thrower_catches_next) the thrower preparing is at_target at the
  // throw's origin this close (mission::ConditionFacts::at_target_within_m), else at 5 cm: the TV-LQR takes up the
  // rest in the throw's first second. A vehicle balancing a caught pole closes its last decimetre
  // at ~5 cm/s (the balancing LQR weighs the pole's tilt far above the position): with 5 cm, a
  // pass's thrower waited 3-4 s at its origin. Passes only: a thrower given the pole by hand is at
  // its origin already, and single throws keep the start their figures were measured with.
  double thrower_at_origin_m = 0.15;
  // A pass (AttemptRequest::thrower_catches_next): the catcher throws back next, and starts down
  // to its own throw's origin once the caught pole has balanced on it this long, while the catch is
  // judged, rather than after it. Measured on the envelope's passes (seeds 1-10): after 1 s a 59 ms
  // catcher carried a still-shaking pole down and threw it so (seed 5: 3 passes in a row against
  // 100 after 2.5 s); 488 passes in all against 427 (docs/architecture.md, "A pass's cadence").
  double pass_return_after_s = 2.5;
};

std::uint32_t attempt_conditions(const AttemptFacts& facts, const AttemptThresholds& thresholds);

// Preparing, the thrower is asked to throw once it is at the throw's origin (at_target, or within
// AttemptThresholds::thrower_at_origin_m in a pass) and the catcher, if the attempt has one, waits
// at its waiting point (at_target in its last condition word).
inline bool throw_due(AttemptPhase phase, bool catch_it, bool thrower_at_origin, mission::Task catcher_task,
                      std::uint32_t catcher_conditions) {
  const bool catcher_ready = !catch_it || (catcher_task == mission::Task::wait &&
                                           (catcher_conditions & mission::condition::at_target));
  return phase == AttemptPhase::preparing && catcher_ready && thrower_at_origin;
}

// The runtime's clocks of a state that must last (the pole balanced on a vehicle): `since_s` is
// when `holds` last became true, none while it does not hold.
inline void hold_since(std::optional<double>& since_s, bool holds, double now_s) {
  if (!holds) since_s.reset();
  else if (!since_s) since_s = now_s;
}

}  // namespace gs::runtime
