// Mission sequencer (groundstation/mission/vehicle_sequencer.hpp): the transition table on its
// own, row by row and as properties over condition words, then VehicleSequencer::step() and
// reset(). Tasks, reasons and condition words print by name so failures read as transitions.
#include <catch2/catch.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "groundstation/mission/vehicle_sequencer.hpp"

namespace Catch {
template <>
struct StringMaker<gs::mission::Task> {
  static std::string convert(gs::mission::Task t) { return std::string(gs::mission::task_name(t)); }
};
template <>
struct StringMaker<gs::mission::Reason> {
  static std::string convert(gs::mission::Reason r) { return std::string(gs::mission::reason_name(r)); }
};
}  // namespace Catch

namespace {

using gs::mission::condition_names;
using gs::mission::find_transition;
using gs::mission::kAirborne;
using gs::mission::kTaskCount;
using gs::mission::kTransitions;
using gs::mission::Reason;
using gs::mission::Task;
using gs::mission::TaskSet;
using gs::mission::task_bit;
using gs::mission::tasks;
using gs::mission::Transition;
using gs::mission::VehicleSequencer;
namespace c = gs::mission::condition;

constexpr std::uint32_t kAllBits = (std::uint32_t{1} << c::kCount) - 1u;
constexpr int kReasonCount = static_cast<int>(Reason::near_floor) + 1;
constexpr int kRowCount = static_cast<int>(kTransitions.size());

std::vector<Task> all_tasks() {
  std::vector<Task> out;
  for (int i = 0; i < kTaskCount; ++i) out.push_back(static_cast<Task>(i));
  return out;
}

bool in(TaskSet set, Task t) { return (set & task_bit(t)) != 0; }
bool airborne(Task t) { return in(kAirborne, t); }

std::string task_list(TaskSet set) {
  std::string out;
  for (Task t : all_tasks()) {
    if (!in(set, t)) continue;
    if (!out.empty()) out += ',';
    out += gs::mission::task_name(t);
  }
  return "{" + out + "}";
}

// "row 13: {balance} [request_throw|settled / not pole_on_self] -> throwing (throw_requested)"
std::string describe_row(int i) {
  if (i < 0) return "no row";
  const Transition& r = kTransitions[static_cast<std::size_t>(i)];
  std::ostringstream s;
  s << "row " << i << ": " << task_list(r.from) << " [" << condition_names(r.all) << " / not "
    << condition_names(r.none) << "] -> " << gs::mission::task_name(r.to) << " ("
    << gs::mission::reason_name(r.reason) << ")";
  return s.str();
}

std::string describe_word(Task t, std::uint32_t word) {
  return std::string(gs::mission::task_name(t)) + " under " + condition_names(word);
}

// The rule read plainly and independently of find_transition: the first row, in table order,
// whose `from` holds the task, all of whose `all` bits hold and none of whose `none` bits do.
int expected_row(Task t, std::uint32_t word) {
  for (int i = 0; i < kRowCount; ++i) {
    const Transition& r = kTransitions[static_cast<std::size_t>(i)];
    const bool from_ok = ((r.from >> static_cast<unsigned>(t)) & 1u) != 0;
    const bool all_ok = (~word & r.all) == 0;   // no required bit missing
    const bool none_ok = (word & r.none) == 0;  // no forbidden bit present
    if (from_ok && all_ok && none_ok) return i;
  }
  return -1;
}

int row_index(const Transition* row) {
  return row == nullptr ? -1 : static_cast<int>(row - kTransitions.data());
}

// The bits any row leaving `t` looks at: the outcome from `t` depends on these alone.
std::uint32_t relevant_bits(Task t) {
  std::uint32_t mask = 0;
  for (const Transition& r : kTransitions)
    if (in(r.from, t)) mask |= r.all | r.none;
  return mask;
}

// Every condition word that matters for `t`: every subset of its relevant bits, first clean (in
// increasing order, so the first failure printed is a small word), then three times with
// pseudo-random noise in the other bits, then `random` fully
// pseudo-random words (half dense, half sparse). The seed is fixed.
template <typename F>
void for_each_word(Task t, F&& f, int random = 20000) {
  std::mt19937 rng(0x5e9u + static_cast<unsigned>(t));
  const std::uint32_t mask = relevant_bits(t);
  for (int noisy = 0; noisy <= 3; ++noisy) {
    std::uint32_t s = 0;
    do {
      f(noisy == 0 ? s : s | (static_cast<std::uint32_t>(rng()) & kAllBits & ~mask));
      s = (s - mask) & mask;  // next subset of mask, back to 0 after the last
    } while (s != 0);
  }
  for (int k = 0; k < random; ++k) {
    std::uint32_t w = static_cast<std::uint32_t>(rng()) & kAllBits;
    if (k % 2) w &= static_cast<std::uint32_t>(rng()) & static_cast<std::uint32_t>(rng());
    f(w);
  }
}

// Counts the words that break a property and remembers the first few, so that one failing
// CHECK prints the task, the word and the row that fired.
struct Violations {
  int count = 0;
  std::string first;
  void add(Task t, std::uint32_t word, const std::string& what) {
    if (count++ < 3)
      first += describe_word(t, word) + ": " + what + " [" + describe_row(expected_row(t, word)) + "]\n";
  }
};

// Whether row i can fire from t at all (is the first match for some word), and one such word.
std::pair<bool, std::uint32_t> witness(int i, Task t) {
  const std::uint32_t mask = relevant_bits(t);
  std::uint32_t s = 0;
  do {
    if (expected_row(t, s) == i) return {true, s};
    s = (s - mask) & mask;
  } while (s != 0);
  return {false, 0};
}

// Where one step from `t` under `word` leads, through VehicleSequencer.
struct Outcome {
  bool changed;
  Task task;
  Reason reason;
};
Outcome step_from(Task t, std::uint32_t word) {
  VehicleSequencer s;
  s.reset(t, 1.0);
  const bool changed = s.step(word, 2.0);
  return {changed, s.task(), s.last_reason()};
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Names
// ---------------------------------------------------------------------------------------------

TEST_CASE("task, reason and condition names are distinct and never '?'", "[sequencer]") {
  std::set<std::string_view> task_names, reason_names, condition_names;
  for (Task t : all_tasks()) {
    INFO("task " << static_cast<int>(t));
    CHECK(gs::mission::task_name(t) != "?");
    CHECK(task_names.insert(gs::mission::task_name(t)).second);
  }
  for (int r = 0; r < kReasonCount; ++r) {
    INFO("reason " << r);
    CHECK(gs::mission::reason_name(static_cast<Reason>(r)) != "?");
    CHECK(reason_names.insert(gs::mission::reason_name(static_cast<Reason>(r))).second);
  }
  for (int b = 0; b < c::kCount; ++b) {
    INFO("condition bit " << b);
    CHECK(gs::mission::condition_name(b) != "?");
    CHECK(condition_names.insert(gs::mission::condition_name(b)).second);
  }
  // Out of range: "?" (and a task or reason added after the last one here shows up as not "?").
  CHECK(gs::mission::task_name(static_cast<Task>(kTaskCount)) == "?");
  CHECK(gs::mission::reason_name(static_cast<Reason>(kReasonCount)) == "?");
  CHECK(gs::mission::condition_name(-1) == "?");
  CHECK(gs::mission::condition_name(c::kCount) == "?");
}

TEST_CASE("condition names follow the bits they name", "[sequencer]") {
  const std::vector<std::pair<std::uint32_t, std::string_view>> named = {
      {c::vehicle_lost, "vehicle_lost"},
      {c::estimate_lost, "estimate_lost"},
      {c::armed, "armed"},
      {c::on_ground, "on_ground"},
      {c::command_failed, "command_failed"},
      {c::at_height, "at_height"},
      {c::at_target, "at_target"},
      {c::pole_on_self, "pole_on_self"},
      {c::pole_free, "pole_free"},
      {c::pole_down, "pole_down"},
      {c::pole_upright, "pole_upright"},
      {c::throw_over, "throw_over"},
      {c::release_over, "release_over"},
      {c::catch_due, "catch_due"},
      {c::catch_unreachable, "catch_unreachable"},
      {c::catch_infeasible, "catch_infeasible"},
      {c::catch_missed, "catch_missed"},
      {c::settled, "settled"},
      {c::request_take_off, "request_take_off"},
      {c::request_throw, "request_throw"},
      {c::request_catch, "request_catch"},
      {c::request_abort, "request_abort"},
      {c::request_land, "request_land"},
      {c::pole_fallen, "pole_fallen"},
  };
  REQUIRE(static_cast<int>(named.size()) == c::kCount);
  std::uint32_t seen = 0;
  for (const auto& [bit, name] : named) {
    INFO(name);
    CHECK((bit & (bit - 1)) == 0);  // one bit
    CHECK((seen & bit) == 0);       // not shared with another condition
    seen |= bit;
    int index = 0;
    while ((std::uint32_t{1} << index) != bit && index < 32) ++index;
    CHECK(gs::mission::condition_name(index) == name);
  }
  CHECK(seen == kAllBits);
}

TEST_CASE("the airborne set is the eleven flying tasks", "[sequencer]") {
  CHECK(kAirborne == tasks(Task::take_off, Task::hover, Task::balance, Task::throwing, Task::release,
                           Task::retreat, Task::wait, Task::catching, Task::rebalance, Task::clear,
                           Task::descend));
  for (Task t : {Task::parked, Task::arming, Task::landing, Task::failsafe}) CHECK_FALSE(airborne(t));
}

// ---------------------------------------------------------------------------------------------
// The table's shape
// ---------------------------------------------------------------------------------------------

TEST_CASE("every row is well formed", "[sequencer]") {
  constexpr TaskSet kAllTasks = (TaskSet{1} << kTaskCount) - 1u;
  for (int i = 0; i < kRowCount; ++i) {
    const Transition& r = kTransitions[static_cast<std::size_t>(i)];
    INFO(describe_row(i));
    CHECK(r.from != 0);
    CHECK((r.from & ~kAllTasks) == 0);
    CHECK((r.all & ~kAllBits) == 0);
    CHECK((r.none & ~kAllBits) == 0);
    CHECK(static_cast<int>(r.to) < kTaskCount);
    CHECK(r.reason != Reason::none);
    // A bit both required and forbidden would make the row dead.
    CHECK((r.all & r.none) == 0);
    // The row leads somewhere from at least one of its tasks ...
    CHECK((r.from & ~task_bit(r.to)) != 0);
    // ... and in fact from all of them: a row that named its own target would fire on itself,
    // step() would ignore it, and it would hide every later row of that task under that word.
    CHECK_FALSE(in(r.from, r.to));
  }
}

TEST_CASE("find_transition is the first matching row in table order", "[sequencer]") {
  std::mt19937 rng(20240611u);
  Violations v;
  int transitions = 0;
  for (int k = 0; k < 300000; ++k) {
    std::uint32_t w = static_cast<std::uint32_t>(rng()) & kAllBits;
    if (k % 3 == 1) w &= static_cast<std::uint32_t>(rng());
    if (k % 3 == 2) w &= static_cast<std::uint32_t>(rng()) & static_cast<std::uint32_t>(rng());
    for (Task t : all_tasks()) {
      const int expected = expected_row(t, w);
      const int got = row_index(find_transition(t, w));
      if (expected >= 0) ++transitions;
      if (got != expected) v.add(t, w, "find_transition gave " + describe_row(got));
    }
  }
  // And exhaustively over the bits each task looks at.
  for (Task t : all_tasks())
    for_each_word(
        t,
        [&](std::uint32_t w) {
          const int got = row_index(find_transition(t, w));
          if (got != expected_row(t, w)) v.add(t, w, "find_transition gave " + describe_row(got));
        },
        0);
  INFO(v.first);
  CHECK(v.count == 0);
  CHECK(transitions > 100000);  // the words exercise the table, not just "no row"
}

// ---------------------------------------------------------------------------------------------
// Every row
// ---------------------------------------------------------------------------------------------

TEST_CASE(
    "each row, from each of its tasks with exactly its `all` bits, is taken unless an earlier row matches",
    "[sequencer]") {
  int shadowed = 0;
  for (int i = 0; i < kRowCount; ++i) {
    const Transition& r = kTransitions[static_cast<std::size_t>(i)];
    for (Task t : all_tasks()) {
      if (!in(r.from, t)) continue;
      const int expected = expected_row(t, r.all);
      INFO(describe_row(i) << ", from " << describe_word(t, r.all) << " -> " << describe_row(expected));
      // The row itself matches (its `all` and `none` do not overlap), so the first match is
      // this row or an earlier one.
      REQUIRE(expected >= 0);
      CHECK(expected <= i);
      CHECK(row_index(find_transition(t, r.all)) == expected);
      const Transition& e = kTransitions[static_cast<std::size_t>(expected)];
      const Outcome o = step_from(t, r.all);
      CHECK(o.changed);
      CHECK(o.task == e.to);
      CHECK(o.reason == e.reason);
      if (expected != i) ++shadowed;
    }
  }
  // Only one (row, task) pair needs more than its `all` bits: balance throws only with the
  // pole on the plate, otherwise the earlier "pole lost" row takes it back to hover.
  CHECK(shadowed == 1);
  const Outcome o = step_from(Task::balance, c::request_throw | c::settled);
  CHECK(o.task == Task::hover);
  CHECK(o.reason == Reason::pole_lost);
}

TEST_CASE("each row can fire from each task in its `from` set", "[sequencer]") {
  for (int i = 0; i < kRowCount; ++i) {
    const Transition& r = kTransitions[static_cast<std::size_t>(i)];
    for (Task t : all_tasks()) {
      if (!in(r.from, t)) continue;
      const auto [found, word] = witness(i, t);
      INFO(describe_row(i) << ", from " << gs::mission::task_name(t));
      CHECK(found);
      if (!found) continue;
      INFO("word " << condition_names(word));
      CHECK(row_index(find_transition(t, word)) == i);
      VehicleSequencer s;
      s.reset(t, 3.0);
      CHECK(s.step(word, 3.5));
      CHECK(s.task() == r.to);
      CHECK(s.last_reason() == r.reason);
      CHECK(s.task_since_s() == 3.5);
    }
  }
}

TEST_CASE("key transitions, written out", "[sequencer]") {
  struct Case {
    Task from;
    std::uint32_t word;
    Task to;  // == from with Reason::none: no row, the task stays
    Reason reason;
  };
  const std::vector<Case> cases = {
      // The throw.
      {Task::throwing, c::throw_over | c::pole_on_self, Task::release, Reason::throw_ended},
      {Task::throwing, c::throw_over, Task::release, Reason::throw_ended},
      {Task::throwing, c::pole_on_self, Task::throwing, Reason::none},
      {Task::throwing, 0, Task::release, Reason::pole_left_early},
      {Task::throwing, c::request_abort | c::pole_on_self, Task::release, Reason::abort_requested},
      {Task::balance, c::request_throw | c::pole_on_self, Task::balance, Reason::none},  // needs settled too
      {Task::balance, c::settled | c::pole_on_self, Task::balance, Reason::none},
      {Task::balance, c::request_throw | c::settled | c::pole_on_self, Task::throwing,
       Reason::throw_requested},
      {Task::balance, 0, Task::hover, Reason::pole_lost},
      {Task::balance, c::request_throw | c::settled, Task::hover, Reason::pole_lost},
      {Task::release, c::release_over, Task::retreat, Reason::released},
      {Task::release, 0, Task::release, Reason::none},
      {Task::retreat, c::at_target, Task::hover, Reason::clear_of_pole},
      {Task::hover, c::pole_on_self | c::pole_upright, Task::balance, Reason::pole_placed},
      {Task::hover, c::pole_on_self, Task::hover, Reason::none},  // fallen over: not balanced
      {Task::balance, c::pole_on_self | c::pole_fallen, Task::hover, Reason::pole_fallen},
      {Task::balance, c::pole_on_self | c::pole_fallen | c::request_throw | c::settled, Task::hover,
       Reason::pole_fallen},
      // The catch.
      {Task::hover, c::request_catch, Task::wait, Reason::catch_requested},
      {Task::hover, c::request_catch | c::pole_on_self | c::pole_upright, Task::balance, Reason::pole_placed},
      {Task::hover, c::request_abort, Task::hover, Reason::none},
      {Task::wait, c::catch_unreachable, Task::clear, Reason::out_of_reach},
      {Task::wait, c::catch_unreachable | c::request_catch, Task::clear, Reason::out_of_reach},
      {Task::catching, c::catch_unreachable | c::request_catch, Task::clear, Reason::out_of_reach},
      {Task::wait, c::catch_infeasible | c::request_catch, Task::clear, Reason::infeasible},
      {Task::catching, c::catch_infeasible, Task::clear, Reason::infeasible},
      {Task::wait, c::request_catch | c::catch_due, Task::catching, Reason::catch_started},
      {Task::wait, c::request_catch, Task::wait, Reason::none},
      {Task::wait, 0, Task::hover, Reason::abort_requested},  // the request withdrawn
      {Task::wait, c::request_abort | c::request_catch, Task::clear, Reason::abort_requested},
      {Task::catching, c::request_abort, Task::clear, Reason::abort_requested},
      {Task::catching, c::pole_on_self, Task::rebalance, Reason::caught},
      {Task::wait, c::pole_on_self | c::request_catch, Task::rebalance, Reason::caught},
      // A caught pole wins over the planner's late verdicts (those rows need the pole not on us).
      {Task::catching, c::pole_on_self | c::catch_unreachable | c::catch_infeasible, Task::rebalance,
       Reason::caught},
      {Task::catching, c::catch_missed, Task::clear, Reason::missed},
      {Task::catching, c::catch_missed | c::pole_down, Task::hover, Reason::pole_down},
      {Task::wait, c::pole_down | c::request_catch, Task::hover, Reason::pole_down},
      {Task::catching, c::request_catch, Task::catching, Reason::none},
      {Task::rebalance, c::pole_on_self | c::pole_upright, Task::balance, Reason::pole_upright},
      {Task::rebalance, c::pole_on_self | c::pole_upright | c::pole_free, Task::rebalance, Reason::none},
      {Task::rebalance, c::pole_on_self, Task::rebalance, Reason::none},
      {Task::rebalance, 0, Task::clear, Reason::pole_lost},
      {Task::clear, c::pole_down, Task::hover, Reason::pole_down},
      {Task::clear, c::settled, Task::hover, Reason::clear_of_pole},
      {Task::clear, c::settled | c::pole_free, Task::clear, Reason::none},
      {Task::clear, c::pole_free, Task::clear, Reason::none},
      // Take-off.
      {Task::parked, 0, Task::parked, Reason::none},
      {Task::parked, c::request_take_off, Task::arming, Reason::take_off_requested},
      {Task::parked, c::request_take_off | c::estimate_lost, Task::parked, Reason::none},
      {Task::parked, c::request_take_off | c::vehicle_lost, Task::parked, Reason::none},
      {Task::parked, c::request_take_off | c::armed | c::on_ground, Task::arming, Reason::take_off_requested},
      {Task::parked, c::armed, Task::hover, Reason::vehicle_back},  // re-attached to a flying vehicle
      {Task::parked, c::armed | c::on_ground, Task::parked, Reason::none},
      {Task::parked, c::armed | c::estimate_lost, Task::parked, Reason::none},
      {Task::parked, c::armed | c::vehicle_lost, Task::parked, Reason::none},
      {Task::parked, c::request_land | c::request_throw | c::request_catch, Task::parked, Reason::none},
      {Task::arming, c::command_failed, Task::parked, Reason::arm_failed},
      {Task::arming, c::command_failed | c::armed, Task::parked, Reason::arm_failed},
      {Task::arming, c::armed, Task::take_off, Reason::armed},
      {Task::arming, c::armed | c::on_ground, Task::take_off, Reason::armed},
      {Task::arming, 0, Task::arming, Reason::none},
      {Task::take_off, c::at_height, Task::hover, Reason::airborne},
      {Task::take_off, c::armed, Task::take_off, Reason::none},
      // Landing: flown down on motion capture, then LAND.
      {Task::hover, c::armed | c::request_land, Task::descend, Reason::land_requested},
      {Task::descend, c::armed, Task::descend, Reason::none},
      {Task::descend, c::armed | c::request_land, Task::descend, Reason::none},  // asked again
      {Task::descend, c::armed | c::at_target, Task::landing, Reason::near_floor},
      {Task::descend, c::armed | c::at_target | c::estimate_lost, Task::failsafe, Reason::estimate_lost},
      {Task::descend, c::at_target | c::vehicle_lost, Task::failsafe, Reason::vehicle_lost},
      {Task::landing, c::on_ground, Task::parked, Reason::landed},
      {Task::landing, c::on_ground | c::armed, Task::landing, Reason::none},  // down but still armed
      {Task::landing, c::armed, Task::landing, Reason::none},
      {Task::landing, c::estimate_lost, Task::landing, Reason::none},  // the vehicle lands on board
      {Task::landing, c::vehicle_lost, Task::failsafe, Reason::vehicle_lost},
      {Task::landing, c::vehicle_lost | c::on_ground, Task::failsafe, Reason::vehicle_lost},
      {Task::landing, c::request_take_off, Task::landing, Reason::none},
      // Failsafe.
      {Task::failsafe, c::on_ground, Task::parked, Reason::landed},
      {Task::failsafe, c::on_ground | c::armed, Task::failsafe, Reason::none},
      {Task::failsafe, c::on_ground | c::vehicle_lost, Task::failsafe, Reason::none},
      {Task::failsafe, c::armed, Task::failsafe, Reason::none},  // heard again, still flying
      {Task::failsafe, 0, Task::failsafe, Reason::none},
      {Task::failsafe, c::request_take_off | c::request_land, Task::failsafe, Reason::none},
  };
  for (const Case& k : cases) {
    INFO(describe_word(k.from, k.word)
         << " -> expected " << gs::mission::task_name(k.to) << " (" << gs::mission::reason_name(k.reason)
         << "), table: " << describe_row(expected_row(k.from, k.word)));
    const Outcome o = step_from(k.from, k.word);
    CHECK(o.task == k.to);
    CHECK(o.reason == k.reason);
    CHECK(o.changed == (k.to != k.from));
    const Transition* row = find_transition(k.from, k.word);
    if (k.to == k.from) {
      CHECK(row == nullptr);
    } else {
      REQUIRE(row != nullptr);
      CHECK(row->to == k.to);
    }
  }
}

TEST_CASE("any airborne task, or landing, that loses the vehicle goes to failsafe", "[sequencer]") {
  for (Task t : all_tasks()) {
    if (!airborne(t) && t != Task::landing) continue;
    INFO(gs::mission::task_name(t));
    for (std::uint32_t extra : {0u, c::request_land, c::request_abort | c::pole_on_self, c::estimate_lost,
                                c::on_ground, kAllBits}) {
      const Outcome o = step_from(t, c::vehicle_lost | extra);
      INFO("with " << condition_names(extra));
      CHECK(o.task == Task::failsafe);
      CHECK(o.reason == Reason::vehicle_lost);
    }
    if (airborne(t)) {
      const Outcome o = step_from(t, c::estimate_lost | c::request_land);
      CHECK(o.task == Task::failsafe);
      CHECK(o.reason == Reason::estimate_lost);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Severity properties over condition words
// ---------------------------------------------------------------------------------------------

TEST_CASE("vehicle_lost in any airborne task always leads to failsafe", "[sequencer]") {
  Violations v;
  for (Task t : all_tasks()) {
    if (!airborne(t) && t != Task::landing) continue;
    for_each_word(t, [&](std::uint32_t w) {
      w |= c::vehicle_lost;
      const Transition* row = find_transition(t, w);
      if (row == nullptr || row->to != Task::failsafe || row->reason != Reason::vehicle_lost)
        v.add(t, w, "not failsafe (vehicle_lost)");
    });
  }
  INFO(v.first);
  CHECK(v.count == 0);
}

TEST_CASE("estimate_lost in any airborne task (vehicle heard) always leads to failsafe", "[sequencer]") {
  Violations v;
  for (Task t : all_tasks()) {
    if (!airborne(t)) continue;
    for_each_word(t, [&](std::uint32_t w) {
      w = (w | c::estimate_lost) & ~c::vehicle_lost;
      const Transition* row = find_transition(t, w);
      if (row == nullptr || row->to != Task::failsafe || row->reason != Reason::estimate_lost)
        v.add(t, w, "not failsafe (estimate_lost)");
    });
  }
  INFO(v.first);
  CHECK(v.count == 0);
}

TEST_CASE(
    "request_land in an airborne task always leads to the descent unless the vehicle or estimate is lost",
    "[sequencer]") {
  Violations v;
  for (Task t : all_tasks()) {
    if (!airborne(t) || t == Task::descend) continue;
    for_each_word(t, [&](std::uint32_t w) {
      w = (w | c::request_land) & ~(c::vehicle_lost | c::estimate_lost);
      const Transition* row = find_transition(t, w);
      if (row == nullptr || row->to != Task::descend || row->reason != Reason::land_requested)
        v.add(t, w, "not descending");
    });
  }
  INFO(v.first);
  CHECK(v.count == 0);
}

TEST_CASE(
    "from parked, the only airborne task reached directly is hover on re-attaching to an armed, flying vehicle",
    "[sequencer]") {
  // The table: rows from parked lead to arming, or to hover only when they need armed and
  // forbid on_ground (and the vehicle and its estimate must be there).
  for (int i = 0; i < kRowCount; ++i) {
    const Transition& r = kTransitions[static_cast<std::size_t>(i)];
    if (!in(r.from, Task::parked) || !airborne(r.to)) continue;
    INFO(describe_row(i));
    CHECK(r.to == Task::hover);
    CHECK((r.all & c::armed) != 0);
    CHECK((r.none & c::on_ground) != 0);
    CHECK((r.none & c::vehicle_lost) != 0);
    CHECK((r.none & c::estimate_lost) != 0);
  }
  // The words.
  Violations v;
  for_each_word(
      Task::parked,
      [&](std::uint32_t w) {
        const Transition* row = find_transition(Task::parked, w);
        if (row == nullptr || row->to == Task::arming) return;
        const bool reattach = row->to == Task::hover && (w & c::armed) && !(w & c::on_ground) &&
                              !(w & (c::vehicle_lost | c::estimate_lost));
        if (!reattach)
          v.add(Task::parked, w, std::string("parked -> ") + std::string(gs::mission::task_name(row->to)));
      },
      300000);
  INFO(v.first);
  CHECK(v.count == 0);
}

TEST_CASE("failsafe is left only to parked, and only once down, disarmed and heard", "[sequencer]") {
  for (int i = 0; i < kRowCount; ++i) {
    const Transition& r = kTransitions[static_cast<std::size_t>(i)];
    if (!in(r.from, Task::failsafe)) continue;
    INFO(describe_row(i));
    CHECK(r.to == Task::parked);
  }
  Violations v;
  for_each_word(
      Task::failsafe,
      [&](std::uint32_t w) {
        const Transition* row = find_transition(Task::failsafe, w);
        if (row == nullptr) return;
        if (row->to != Task::parked) v.add(Task::failsafe, w, "left failsafe, not to parked");
        if (!(w & c::on_ground) || (w & (c::armed | c::vehicle_lost)))
          v.add(Task::failsafe, w, "parked too early");
      },
      300000);
  INFO(v.first);
  CHECK(v.count == 0);
}

TEST_CASE(
    "nothing but the operator's land leads into landing, through the descent, and landing only ends down or lost",
    "[sequencer]") {
  for (int i = 0; i < kRowCount; ++i) {
    const Transition& r = kTransitions[static_cast<std::size_t>(i)];
    INFO(describe_row(i));
    if (r.to == Task::descend) CHECK(r.reason == Reason::land_requested);
    if (r.to == Task::landing) {
      CHECK(r.from == tasks(Task::descend));
      CHECK(r.reason == Reason::near_floor);
    }
    if (in(r.from, Task::landing)) CHECK((r.to == Task::failsafe || r.to == Task::parked));
  }
}

TEST_CASE("no transition enters an airborne task while the vehicle or its estimate is lost", "[sequencer]") {
  // TABLE PROBLEM (reported, not fixed here): the row {arming} [armed] -> take_off forbids
  // neither vehicle_lost nor estimate_lost, so an arming vehicle that is lost, or whose pose
  // estimate is stale, is sent to take_off (e.g. arming under armed|vehicle_lost or
  // armed|estimate_lost), to be dropped into failsafe on the next step. Kept as CHECK so the
  // rest of the suite runs.
  Violations v;
  for (Task t : all_tasks()) {
    for_each_word(t, [&](std::uint32_t word) {
      for (std::uint32_t lost : {c::vehicle_lost, c::estimate_lost, c::vehicle_lost | c::estimate_lost}) {
        const std::uint32_t w = word | lost;
        const Transition* row = find_transition(t, w);
        if (row != nullptr && airborne(row->to))
          v.add(t, w, std::string("entered ") + std::string(gs::mission::task_name(row->to)));
      }
    });
  }
  INFO(v.first);
  CHECK(v.count == 0);
}

// ---------------------------------------------------------------------------------------------
// Reachability
// ---------------------------------------------------------------------------------------------

namespace {
// Edges of the table that can actually fire (some word makes the row the first match).
std::vector<std::pair<Task, Task>> live_edges() {
  std::vector<std::pair<Task, Task>> edges;
  for (int i = 0; i < kRowCount; ++i)
    for (Task t : all_tasks())
      if (in(kTransitions[static_cast<std::size_t>(i)].from, t) && witness(i, t).first)
        edges.emplace_back(t, kTransitions[static_cast<std::size_t>(i)].to);
  return edges;
}

TaskSet reachable_from(Task start, const std::vector<std::pair<Task, Task>>& edges) {
  TaskSet seen = task_bit(start);
  std::vector<Task> queue{start};
  while (!queue.empty()) {
    const Task t = queue.back();
    queue.pop_back();
    for (const auto& [from, to] : edges)
      if (from == t && !in(seen, to)) {
        seen |= task_bit(to);
        queue.push_back(to);
      }
  }
  return seen;
}
}  // namespace

TEST_CASE("every task is reachable from parked, and parked from every task", "[sequencer]") {
  const auto edges = live_edges();
  const TaskSet from_parked = reachable_from(Task::parked, edges);
  for (Task t : all_tasks()) {
    INFO(gs::mission::task_name(t) << ", reachable from parked: " << task_list(from_parked));
    CHECK(in(from_parked, t));
    // Every task has a way back to the ground (through landing, failsafe or a refused ARM).
    const TaskSet from_t = reachable_from(t, edges);
    INFO("reachable from " << gs::mission::task_name(t) << ": " << task_list(from_t));
    CHECK(in(from_t, Task::parked));
  }
}

TEST_CASE("a mission's tasks are reached in the order the paper flies them", "[sequencer]") {
  const auto edges = live_edges();
  auto edge = [&](Task a, Task b) {
    for (const auto& e : edges)
      if (e.first == a && e.second == b) return true;
    return false;
  };
  // The thrower.
  CHECK(edge(Task::parked, Task::arming));
  CHECK(edge(Task::arming, Task::take_off));
  CHECK(edge(Task::take_off, Task::hover));
  CHECK(edge(Task::hover, Task::balance));
  CHECK(edge(Task::balance, Task::throwing));
  CHECK(edge(Task::throwing, Task::release));
  CHECK(edge(Task::release, Task::retreat));
  CHECK(edge(Task::retreat, Task::hover));
  // The catcher.
  CHECK(edge(Task::hover, Task::wait));
  CHECK(edge(Task::wait, Task::catching));
  CHECK(edge(Task::catching, Task::rebalance));
  CHECK(edge(Task::rebalance, Task::balance));
  // And no shortcut: the throw only starts from balance, the catch only from wait.
  for (const auto& [from, to] : edges) {
    INFO(gs::mission::task_name(from) << " -> " << gs::mission::task_name(to));
    if (to == Task::throwing) CHECK(from == Task::balance);
    if (to == Task::catching) CHECK(from == Task::wait);
    if (to == Task::take_off) CHECK(from == Task::arming);
    if (to == Task::arming) CHECK(from == Task::parked);
  }
}

// ---------------------------------------------------------------------------------------------
// VehicleSequencer
// ---------------------------------------------------------------------------------------------

TEST_CASE("a new sequencer is parked since 0 with no reason", "[sequencer]") {
  const VehicleSequencer s;
  CHECK(s.task() == Task::parked);
  CHECK(s.task_since_s() == 0.0);
  CHECK(s.last_reason() == Reason::none);
  CHECK(s.last_conditions() == 0u);
}

TEST_CASE("step takes at most one transition, the first matching row's", "[sequencer]") {
  Violations v;
  int chained = 0;  // words under which the new task would move on again
  for (Task t : all_tasks()) {
    for_each_word(
        t,
        [&](std::uint32_t w) {
          VehicleSequencer s;
          s.reset(t, 10.0);
          const bool changed = s.step(w, 11.0);
          const int expected = expected_row(t, w);
          if (s.last_conditions() != w) v.add(t, w, "last_conditions not the word");
          if (expected < 0) {
            if (changed || s.task() != t || s.task_since_s() != 10.0 || s.last_reason() != Reason::none)
              v.add(t, w, "changed without a row");
            return;
          }
          const Transition& r = kTransitions[static_cast<std::size_t>(expected)];
          if (!changed || s.task() != r.to || s.task_since_s() != 11.0 || s.last_reason() != r.reason)
            v.add(t, w, std::string("ended in ") + std::string(gs::mission::task_name(s.task())));
          if (find_transition(r.to, w) != nullptr) ++chained;
        },
        2000);
  }
  INFO(v.first);
  CHECK(v.count == 0);
  CHECK(chained > 0);  // the words did offer a second transition, and step() did not take it
}

TEST_CASE("step: one transition per call, since only on change, the reason kept", "[sequencer]") {
  VehicleSequencer s;
  // arming under armed|at_height: arming -> take_off, and take_off would go on to hover.
  s.reset(Task::arming, 1.0);
  const std::uint32_t w = c::armed | c::at_height;
  CHECK(s.step(w, 1.5));
  CHECK(s.task() == Task::take_off);
  CHECK(s.task_since_s() == 1.5);
  CHECK(s.last_reason() == Reason::armed);
  CHECK(s.last_conditions() == w);
  CHECK(s.step(w, 1.6));
  CHECK(s.task() == Task::hover);
  CHECK(s.task_since_s() == 1.6);
  CHECK(s.last_reason() == Reason::airborne);
  // Nothing matches: the task, its start time and the last reason stay; the conditions update.
  CHECK_FALSE(s.step(c::armed, 2.0));
  CHECK_FALSE(s.step(c::armed | c::settled, 3.0));
  CHECK(s.task() == Task::hover);
  CHECK(s.task_since_s() == 1.6);
  CHECK(s.last_reason() == Reason::airborne);
  CHECK(s.last_conditions() == (c::armed | c::settled));
}

TEST_CASE("reset forces a task, restarts its clock and clears the reason", "[sequencer]") {
  VehicleSequencer s;
  CHECK(s.step(c::request_take_off, 1.0));
  REQUIRE(s.task() == Task::arming);
  REQUIRE(s.last_reason() == Reason::take_off_requested);

  s.reset(Task::hover, 5.0);  // re-attaching to a vehicle that already flies
  CHECK(s.task() == Task::hover);
  CHECK(s.task_since_s() == 5.0);
  CHECK(s.last_reason() == Reason::none);
  // The table runs from the forced task.
  CHECK(s.step(c::armed | c::pole_on_self | c::pole_upright, 5.1));
  CHECK(s.task() == Task::balance);
  CHECK(s.last_reason() == Reason::pole_placed);

  // Resetting to the same task still restarts its clock.
  s.reset(Task::balance, 9.0);
  CHECK(s.task() == Task::balance);
  CHECK(s.task_since_s() == 9.0);
  CHECK(s.last_reason() == Reason::none);
}

TEST_CASE("a throw and a catch, step by step", "[sequencer]") {
  using W = std::uint32_t;
  struct Step {
    W word;
    Task task;
    Reason reason;
  };
  const W up = c::armed;
  const W pole = up | c::pole_on_self;
  SECTION("the thrower") {
    const std::vector<Step> steps = {
        {0, Task::parked, Reason::none},
        {c::request_take_off | c::on_ground, Task::arming, Reason::take_off_requested},
        {c::on_ground, Task::arming, Reason::take_off_requested},
        {up | c::on_ground, Task::take_off, Reason::armed},
        {up, Task::take_off, Reason::armed},
        {up | c::at_height, Task::hover, Reason::airborne},
        {pole | c::pole_upright, Task::balance, Reason::pole_placed},
        {pole | c::request_throw, Task::balance, Reason::pole_placed},
        {pole | c::request_throw | c::settled, Task::throwing, Reason::throw_requested},
        {pole, Task::throwing, Reason::throw_requested},
        {pole | c::throw_over, Task::release, Reason::throw_ended},
        {up | c::pole_free, Task::release, Reason::throw_ended},
        {up | c::pole_free | c::release_over, Task::retreat, Reason::released},
        {up | c::pole_free | c::at_target, Task::hover, Reason::clear_of_pole},
        {up | c::request_land, Task::descend, Reason::land_requested},
        {up, Task::descend, Reason::land_requested},
        {up | c::at_target, Task::landing, Reason::near_floor},
        {up | c::on_ground, Task::landing, Reason::near_floor},
        {c::on_ground, Task::parked, Reason::landed},
    };
    VehicleSequencer s;
    double t = 0.0, since = 0.0;
    Task previous = Task::parked;
    for (std::size_t i = 0; i < steps.size(); ++i) {
      t += 0.01;
      INFO("step " << i << ": " << describe_word(previous, steps[i].word));
      const bool changed = s.step(steps[i].word, t);
      CHECK(changed == (steps[i].task != previous));
      if (changed) since = t;
      CHECK(s.task() == steps[i].task);
      CHECK(s.last_reason() == steps[i].reason);
      CHECK(s.task_since_s() == since);
      previous = s.task();
    }
  }
  SECTION("the catcher") {
    VehicleSequencer s;
    s.reset(Task::hover, 0.0);
    const std::vector<Step> steps = {
        {up | c::request_catch, Task::wait, Reason::catch_requested},
        {up | c::request_catch | c::pole_free, Task::wait, Reason::catch_requested},
        {up | c::request_catch | c::pole_free | c::catch_due, Task::catching, Reason::catch_started},
        {up | c::request_catch | c::pole_free, Task::catching, Reason::catch_started},
        {pole | c::request_catch, Task::rebalance, Reason::caught},
        {pole, Task::rebalance, Reason::caught},
        {pole | c::pole_upright, Task::balance, Reason::pole_upright},
    };
    Task previous = Task::hover;
    for (std::size_t i = 0; i < steps.size(); ++i) {
      INFO("step " << i << ": " << describe_word(previous, steps[i].word));
      s.step(steps[i].word, 1.0 + static_cast<double>(i));
      CHECK(s.task() == steps[i].task);
      CHECK(s.last_reason() == steps[i].reason);
      previous = s.task();
    }
  }
  SECTION("a missed catch") {
    VehicleSequencer s;
    s.reset(Task::catching, 0.0);
    CHECK(s.step(up | c::request_catch | c::pole_free | c::catch_missed, 1.0));
    CHECK(s.task() == Task::clear);
    CHECK(s.last_reason() == Reason::missed);
    CHECK_FALSE(s.step(up | c::pole_free | c::settled, 2.0));  // the pole still falling
    CHECK(s.step(up | c::pole_down, 3.0));
    CHECK(s.task() == Task::hover);
    CHECK(s.last_reason() == Reason::pole_down);
  }
}
