#include "groundstation/runtime/attempt_phases.hpp"

namespace gs::runtime {

std::string_view phase_name(AttemptPhase phase) {
  switch (phase) {
    case AttemptPhase::idle: return "idle";
    case AttemptPhase::preparing: return "preparing";
    case AttemptPhase::throwing: return "throwing";
    case AttemptPhase::flight: return "flight";
    case AttemptPhase::balancing: return "balancing";
  }
  return "?";
}

std::string_view attempt_condition_name(int bit) {
  static constexpr std::array<std::string_view, attempt_condition::kCount> kNames = {
      "catcher_lost",  "thrower_throwing", "thrower_releasing", "launched",           "catcher_balancing",
      "balanced_long", "pole_down",        "timed_out",         "motors_unidentified"};
  return bit >= 0 && bit < attempt_condition::kCount ? kNames[static_cast<std::size_t>(bit)] : "?";
}

std::string attempt_condition_names(std::uint32_t word) {
  return mission::bit_names(word, attempt_condition::kCount, attempt_condition_name);
}

std::string_view attempt_end_name(AttemptEnd end) {
  switch (end) {
    case AttemptEnd::none: return "none";
    case AttemptEnd::catcher_lost: return "catcher_lost";
    case AttemptEnd::motors_unidentified: return "motors_unidentified";
    case AttemptEnd::throw_abandoned: return "throw_abandoned";
    case AttemptEnd::caught: return "caught";
    case AttemptEnd::pole_down: return "pole_down";
    case AttemptEnd::timed_out: return "timed_out";
  }
  return "?";
}

const AttemptTransition* find_attempt_transition(AttemptPhase phase, std::uint32_t conditions) {
  return mission::first_matching_row(kAttemptTransitions, phase_bit(phase), conditions);
}

const AttemptTransition* settle_attempt(AttemptPhase& phase, std::uint32_t conditions) {
  const AttemptTransition* last = nullptr;
  // No row keeps its phase and none leads back (attempt_phases_test): this ends.
  while (const AttemptTransition* row = find_attempt_transition(phase, conditions)) {
    last = row;
    phase = row->to;
  }
  return last;
}

std::uint32_t attempt_conditions(const AttemptFacts& f, const AttemptThresholds& t) {
  namespace ac = attempt_condition;
  using mission::Task;
  std::uint32_t w = 0;
  if (f.catch_it && f.catcher_task == Task::failsafe && !f.impact && !f.catcher_end_noted)
    w |= ac::catcher_lost;
  if (f.motors_unidentified) w |= ac::motors_unidentified;
  if (f.thrower_task == Task::throwing) w |= ac::thrower_throwing;
  if (f.thrower_task == Task::release) w |= ac::thrower_releasing;
  // Only a call at the end of the throw (see the conditions on the flip-flops during it).
  if (f.free_flight_call_s &&
      *f.free_flight_call_s > f.throw_start_s + f.throw_duration_s - t.launch_call_window_s)
    w |= ac::launched;
  if (f.catcher_task == Task::balance) w |= ac::catcher_balancing;
  if (f.catcher_balancing_since_s && f.now_s - *f.catcher_balancing_since_s >= t.caught_after_s)
    w |= ac::balanced_long;
  if (f.pole_seen_height_m && *f.pole_seen_height_m < t.pole_down_height_m) w |= ac::pole_down;
  if (f.now_s - f.throw_start_s > t.attempt_timeout_s) w |= ac::timed_out;
  return w;
}

}  // namespace gs::runtime
