// The attempt's phases (groundstation/runtime/attempt_phases.hpp): the table's rows written out
// and its properties over every condition word, failures printed with names; then each condition
// bit's rule from plain facts.
#include <catch2/catch.hpp>

#include <set>
#include <string>

#include "groundstation/runtime/attempt_phases.hpp"

namespace {

using gs::mission::Task;
using gs::runtime::attempt_condition_name;
using gs::runtime::attempt_condition_names;
using gs::runtime::attempt_conditions;
using gs::runtime::AttemptEnd;
using gs::runtime::AttemptFacts;
using gs::runtime::AttemptPhase;
using gs::runtime::AttemptThresholds;
using gs::runtime::find_attempt_transition;
using gs::runtime::kAttemptTransitions;
using gs::runtime::phase_bit;
namespace ac = gs::runtime::attempt_condition;

constexpr std::uint32_t kAllWords = 1u << ac::kCount;
const AttemptPhase kPhases[] = {AttemptPhase::idle, AttemptPhase::preparing, AttemptPhase::throwing,
                                AttemptPhase::flight, AttemptPhase::balancing};

// "preparing --[thrower_throwing]--> throwing (none)", or "preparing stays under ..." for no row.
std::string step(AttemptPhase from, std::uint32_t word) {
  const gs::runtime::AttemptTransition* row = find_attempt_transition(from, word);
  const std::string f(gs::runtime::phase_name(from));
  if (row == nullptr) return f + " stays under " + attempt_condition_names(word);
  return f + " --[" + attempt_condition_names(word) + "]--> " +
         std::string(gs::runtime::phase_name(row->to)) + " (" +
         std::string(gs::runtime::attempt_end_name(row->reason)) + ")";
}

}  // namespace

TEST_CASE("Phase, condition and end names are distinct and never '?'") {
  std::set<std::string_view> names;
  for (AttemptPhase p : kPhases) names.insert(gs::runtime::phase_name(p));
  CHECK(names.size() == std::size(kPhases));
  names.clear();
  for (int b = 0; b < ac::kCount; ++b) names.insert(attempt_condition_name(b));
  CHECK(names.size() == static_cast<std::size_t>(ac::kCount));
  CHECK(names.count("?") == 0);
  CHECK(attempt_condition_name(ac::kCount) == "?");
  names.clear();
  for (AttemptEnd e :
       {AttemptEnd::none, AttemptEnd::catcher_lost, AttemptEnd::motors_unidentified,
        AttemptEnd::throw_abandoned, AttemptEnd::caught, AttemptEnd::pole_down, AttemptEnd::timed_out})
    names.insert(gs::runtime::attempt_end_name(e));
  CHECK(names.size() == 7);
  CHECK(names.count("?") == 0);
  CHECK(attempt_condition_names(0) == "0");
  CHECK(attempt_condition_names(ac::launched | ac::pole_down) == "launched|pole_down");
}

TEST_CASE("Every row is well formed: ends go to idle with a reason, steps go on without one") {
  for (const auto& row : kAttemptTransitions) {
    CAPTURE(gs::runtime::phase_name(row.to), gs::runtime::attempt_end_name(row.reason));
    CHECK(row.from != 0);
    CHECK((row.from & phase_bit(AttemptPhase::idle)) == 0);  // an idle station has no attempt
    CHECK((row.all & row.none) == 0);
    CHECK((row.to == AttemptPhase::idle) == (row.reason != AttemptEnd::none));
    CHECK((row.from & phase_bit(row.to)) == 0);  // no row keeps its phase
    // A row stays on its side of the launch, but for the launch itself.
    const bool before = (row.from & gs::runtime::kBeforeLaunch) != 0;
    CHECK((row.from & (before ? gs::runtime::kInFlight : gs::runtime::kBeforeLaunch)) == 0);
  }
}

TEST_CASE("Idle takes no row under any word") {
  for (std::uint32_t w = 0; w < kAllWords; ++w)
    CHECK(find_attempt_transition(AttemptPhase::idle, w) == nullptr);
}

TEST_CASE("The attempt's course, written out") {
  CHECK(step(AttemptPhase::preparing, 0) == "preparing stays under 0");
  CHECK(step(AttemptPhase::preparing, ac::thrower_throwing) ==
        "preparing --[thrower_throwing]--> throwing (none)");
  CHECK(step(AttemptPhase::preparing, ac::catcher_lost | ac::thrower_throwing) ==
        "preparing --[catcher_lost|thrower_throwing]--> idle (catcher_lost)");
  CHECK(step(AttemptPhase::preparing, ac::motors_unidentified) ==
        "preparing --[motors_unidentified]--> idle (motors_unidentified)");
  // Once thrown, the motors' identification no longer matters: the pole is in the air.
  CHECK(step(AttemptPhase::throwing, ac::motors_unidentified | ac::thrower_throwing) ==
        "throwing stays under thrower_throwing|motors_unidentified");
  CHECK(step(AttemptPhase::throwing, ac::thrower_throwing) == "throwing stays under thrower_throwing");
  CHECK(step(AttemptPhase::throwing, ac::thrower_releasing) == "throwing stays under thrower_releasing");
  CHECK(step(AttemptPhase::throwing, ac::thrower_releasing | ac::launched) ==
        "throwing --[thrower_releasing|launched]--> flight (none)");
  CHECK(step(AttemptPhase::throwing, 0) == "throwing --[0]--> idle (throw_abandoned)");
  CHECK(step(AttemptPhase::throwing, ac::launched) == "throwing --[launched]--> flight (none)");
  // A catcher lost once the pole flies does not end the attempt: the pole coming down does.
  CHECK(step(AttemptPhase::throwing, ac::catcher_lost | ac::thrower_releasing) ==
        "throwing stays under catcher_lost|thrower_releasing");
  CHECK(step(AttemptPhase::flight, ac::catcher_lost) == "flight stays under catcher_lost");
  CHECK(step(AttemptPhase::flight, ac::catcher_balancing) ==
        "flight --[catcher_balancing]--> balancing (none)");
  CHECK(step(AttemptPhase::balancing, ac::catcher_balancing) == "balancing stays under catcher_balancing");
  CHECK(step(AttemptPhase::balancing, ac::catcher_balancing | ac::balanced_long) ==
        "balancing --[catcher_balancing|balanced_long]--> idle (caught)");
  CHECK(step(AttemptPhase::flight, ac::pole_down | ac::timed_out) ==
        "flight --[pole_down|timed_out]--> idle (pole_down)");
  CHECK(step(AttemptPhase::balancing, ac::timed_out) == "balancing --[timed_out]--> idle (timed_out)");
  // Caught outranks the pole seen low and the time.
  CHECK(step(AttemptPhase::balancing,
             ac::catcher_balancing | ac::balanced_long | ac::pole_down | ac::timed_out) ==
        "balancing --[catcher_balancing|balanced_long|pole_down|timed_out]--> idle (caught)");
}

TEST_CASE("Properties over every condition word") {
  for (std::uint32_t w = 0; w < kAllWords; ++w) {
    for (AttemptPhase p : kPhases) {
      const auto* row = find_attempt_transition(p, w);
      if (row == nullptr) continue;
      INFO(step(p, w));
      // Before the throw only the catcher lost or motors not identified end it; in flight nothing
      // but the four ends and the catcher's balance moves it.
      if (p == AttemptPhase::preparing && row->to == AttemptPhase::idle)
        CHECK((row->reason == AttemptEnd::catcher_lost || row->reason == AttemptEnd::motors_unidentified));
      if (p == AttemptPhase::preparing && row->to != AttemptPhase::idle)
        CHECK((w & ac::thrower_throwing) != 0);
      // The launch is never skipped: flight comes only from throwing, with the call.
      if (row->to == AttemptPhase::flight) CHECK((p == AttemptPhase::throwing && (w & ac::launched)));
      // Only a launch or a throw still flown keeps a throwing attempt alive.
      if (p == AttemptPhase::throwing && row->to == AttemptPhase::idle)
        CHECK((w & (ac::launched | ac::thrower_throwing | ac::thrower_releasing)) == 0);
      // Caught only balanced on the catcher long enough, and only after the launch.
      if (row->reason == AttemptEnd::caught) {
        CHECK((w & ac::balanced_long) != 0);
        CHECK((p == AttemptPhase::flight || p == AttemptPhase::balancing));
      }
    }
    // In flight, settled under one word: the attempt ends exactly when the pole is down, the
    // time is up or the catcher has balanced long enough; else a balancing catcher makes it
    // balancing and nothing else moves it.
    for (AttemptPhase p : {AttemptPhase::flight, AttemptPhase::balancing}) {
      INFO(step(p, w));
      const bool ends =
          (w & (ac::pole_down | ac::timed_out)) != 0 ||
          (w & (ac::catcher_balancing | ac::balanced_long)) == (ac::catcher_balancing | ac::balanced_long);
      AttemptPhase settled = p;
      gs::runtime::settle_attempt(settled, w);
      const AttemptPhase expected = ends                          ? AttemptPhase::idle
                                    : (w & ac::catcher_balancing) ? AttemptPhase::balancing
                                                                  : p;
      CHECK(gs::runtime::phase_name(settled) == gs::runtime::phase_name(expected));
    }
  }
}

namespace {

// An attempt 0.5 s into its flight: thrown at 10 s, a 1.1 s throw, launched at 11.1 s.
AttemptFacts in_flight() {
  AttemptFacts f;
  f.thrower_task = Task::release;
  f.catcher_task = Task::catching;
  f.now_s = 11.6;
  f.throw_start_s = 10.0;
  f.throw_duration_s = 1.1;
  f.free_flight_call_s = 11.1;
  f.pole_seen_height_m = 2.5;
  return f;
}

}  // namespace

TEST_CASE("Each condition bit from its facts") {
  const AttemptThresholds t;
  CHECK(attempt_condition_names(attempt_conditions(in_flight(), t)) == "thrower_releasing|launched");
  AttemptFacts f = in_flight();
  f.catcher_task = Task::failsafe;
  CHECK(attempt_condition_names(attempt_conditions(f, t)) == "catcher_lost|thrower_releasing|launched");
  f.impact = true;  // after the impact a failsafe is not a lost catch
  CHECK((attempt_conditions(f, t) & ac::catcher_lost) == 0);
  f.impact = false;
  f.catcher_end_noted = true;  // noted once
  CHECK((attempt_conditions(f, t) & ac::catcher_lost) == 0);
  f.catcher_end_noted = false;
  f.catch_it = false;  // no catcher
  CHECK((attempt_conditions(f, t) & ac::catcher_lost) == 0);

  f = in_flight();
  f.motors_unidentified = true;
  CHECK((attempt_conditions(f, t) & ac::motors_unidentified) != 0);

  f = in_flight();
  f.thrower_task = Task::throwing;
  CHECK((attempt_conditions(f, t) & (ac::thrower_throwing | ac::thrower_releasing)) == ac::thrower_throwing);
}

TEST_CASE("The launch is a call to free flight within launch_call_window_s of the throw's end") {
  const AttemptThresholds t;
  AttemptFacts f = in_flight();
  f.free_flight_call_s = f.throw_start_s + f.throw_duration_s - t.launch_call_window_s + 0.001;
  CHECK((attempt_conditions(f, t) & ac::launched) != 0);
  f.free_flight_call_s = f.throw_start_s + f.throw_duration_s - t.launch_call_window_s - 0.001;
  CHECK((attempt_conditions(f, t) & ac::launched) == 0);  // a flip during the throw
  f.free_flight_call_s.reset();
  CHECK((attempt_conditions(f, t) & ac::launched) == 0);
}

TEST_CASE("Balanced long, the pole down and the time up, each at its threshold") {
  const AttemptThresholds t;
  AttemptFacts f = in_flight();
  f.catcher_task = Task::balance;
  f.catcher_balancing_since_s = f.now_s - t.caught_after_s;
  CHECK(attempt_condition_names(attempt_conditions(f, t) & (ac::catcher_balancing | ac::balanced_long)) ==
        "catcher_balancing|balanced_long");
  f.catcher_balancing_since_s = f.now_s - t.caught_after_s + 0.001;
  CHECK((attempt_conditions(f, t) & ac::balanced_long) == 0);
  f = in_flight();
  f.pole_seen_height_m = t.pole_down_height_m - 0.001;
  CHECK((attempt_conditions(f, t) & ac::pole_down) != 0);
  f.pole_seen_height_m = t.pole_down_height_m;
  CHECK((attempt_conditions(f, t) & ac::pole_down) == 0);
  f.pole_seen_height_m.reset();  // never seen
  CHECK((attempt_conditions(f, t) & ac::pole_down) == 0);
  f = in_flight();
  f.now_s = f.throw_start_s + t.attempt_timeout_s;
  CHECK((attempt_conditions(f, t) & ac::timed_out) == 0);
  f.now_s = f.throw_start_s + t.attempt_timeout_s + 0.001;
  CHECK((attempt_conditions(f, t) & ac::timed_out) != 0);
}

TEST_CASE("hold_since: when the state last began to hold, none while it does not") {
  std::optional<double> since;
  gs::runtime::hold_since(since, false, 1.0);
  CHECK_FALSE(since);
  gs::runtime::hold_since(since, true, 2.0);
  REQUIRE(since);
  CHECK(*since == 2.0);
  gs::runtime::hold_since(since, true, 3.0);
  CHECK(*since == 2.0);  // still the start
  gs::runtime::hold_since(since, false, 4.0);
  CHECK_FALSE(since);
  gs::runtime::hold_since(since, true, 5.0);
  CHECK(*since == 5.0);
}

TEST_CASE("throw_due: preparing, the thrower at the origin and the catcher waiting at its point") {
  namespace cond = gs::mission::condition;
  using gs::runtime::throw_due;
  CHECK(throw_due(AttemptPhase::preparing, true, true, Task::wait, cond::at_target));
  CHECK_FALSE(throw_due(AttemptPhase::preparing, true, false, Task::wait, cond::at_target));
  CHECK_FALSE(throw_due(AttemptPhase::preparing, true, true, Task::wait, 0));
  CHECK_FALSE(throw_due(AttemptPhase::preparing, true, true, Task::hover, cond::at_target));
  CHECK(throw_due(AttemptPhase::preparing, false, true, Task::hover, 0));  // no catch
  for (AttemptPhase p :
       {AttemptPhase::idle, AttemptPhase::throwing, AttemptPhase::flight, AttemptPhase::balancing})
    CHECK_FALSE(throw_due(p, true, true, Task::wait, cond::at_target));
}
