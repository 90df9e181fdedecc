// The mission sequencer of one vehicle: what it is doing (its task) and when it moves on, as a
// table-driven state machine in the shape of the firmware's supervisor (fw/supervisor.hpp).
//
// Every step() the runtime turns what it knows into a word of condition bits (the link's view
// of the vehicle, the estimator's pole mode, the planner's verdicts, the attempt's clock, the
// operator's requests); the constexpr table kTransitions lists, in order, the rows "from any of
// these tasks, when all of these bits hold and none of those, go to that task with this
// reason"; the first matching row wins, one transition per step. The rows are ordered by
// severity: losing the vehicle or its estimate first, then the operator's land and abort, then
// the mission's own progress. The sequencer knows nothing of controllers: the runtime flies
// each task with its controller (runtime/task_control.hpp).
//
// One table serves the thrower and the catcher: which rows apply follows from the task the
// vehicle is in (only the vehicle carrying the pole is ever asked to throw, only the other one
// to catch), so a vehicle that catches can throw the next time.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

#include "groundstation/mission/transition_table.hpp"

namespace gs::mission {

enum class Task : std::uint8_t {
  parked,     // on the ground, disarmed (or never heard)
  arming,     // zero-thrust setpoints and ARM sent, waiting for the vehicle's armed flag
  take_off,   // climbing to the take-off height over where it stood
  hover,      // holding a point, no pole
  balance,    // holding a point with the pole balanced on the plate (Section VII-A)
  throwing,   // tracking the optimal throw (TV-LQR, Section VII-A) to its end T
  release,    // after T: thrust down and the plate pitching back, so that the pole leaves it
  retreat,    // flying clear of the pole's flight path, then hover
  wait,       // at the catch manoeuvre's waiting point (Section V)
  catching,   // the catch manoeuvre, re-planned from each catch-point prediction
  rebalance,  // the pole caught: holding still while it swings up, then balance
  clear,      // catch aborted: hovering clear of the falling pole
  landing,    // LAND sent; the vehicle descends on board and disarms
  failsafe,   // vehicle or its estimate lost: no setpoints (the firmware levels and lands)
  // Flying down on motion capture to just above the floor, where LAND takes over (after the
  // others so that the numbers logged before it keep theirs).
  descend,
};
inline constexpr int kTaskCount = 15;
std::string_view task_name(Task task);

// Sets of tasks for the rows' `from`.
using TaskSet = std::uint32_t;
constexpr TaskSet task_bit(Task t) { return TaskSet{1} << static_cast<unsigned>(t); }
template <typename... T>
constexpr TaskSet tasks(T... t) {
  return (task_bit(t) | ...);
}
inline constexpr TaskSet kAirborne =
    tasks(Task::take_off, Task::hover, Task::balance, Task::throwing, Task::release, Task::retreat,
          Task::wait, Task::catching, Task::rebalance, Task::clear, Task::descend);

// The condition bits (computed by the runtime each step).
namespace condition {
inline constexpr std::uint32_t vehicle_lost = 1u << 0;        // no VEHICLE_HEARTBEAT within the timeout
inline constexpr std::uint32_t estimate_lost = 1u << 1;       // the vehicle's pose estimate is stale
inline constexpr std::uint32_t armed = 1u << 2;               // the vehicle reports armed
inline constexpr std::uint32_t on_ground = 1u << 3;           // landed / disarmed on the floor
inline constexpr std::uint32_t command_failed = 1u << 4;      // ARM refused or timed out
inline constexpr std::uint32_t at_height = 1u << 5;           // take-off height reached
inline constexpr std::uint32_t at_target = 1u << 6;           // at the task's point, nearly at rest
inline constexpr std::uint32_t pole_on_self = 1u << 7;        // the estimator: pole on this vehicle
inline constexpr std::uint32_t pole_free = 1u << 8;           // the estimator: pole in free flight
inline constexpr std::uint32_t pole_down = 1u << 9;           // the pole lies on the floor
inline constexpr std::uint32_t pole_upright = 1u << 10;       // the pole on this plate near upright
inline constexpr std::uint32_t throw_over = 1u << 11;         // the throw's time T has passed
inline constexpr std::uint32_t release_over = 1u << 12;       // the release manoeuvre has ended
inline constexpr std::uint32_t catch_due = 1u << 13;          // time to start the catch manoeuvre
inline constexpr std::uint32_t catch_unreachable = 1u << 14;  // prediction out of reach
inline constexpr std::uint32_t catch_infeasible = 1u << 15;   // planner: inputs beyond limits
inline constexpr std::uint32_t catch_missed = 1u << 16;       // the pole passed the plate unheld
inline constexpr std::uint32_t settled = 1u << 17;            // held the task's point long enough
// Requests (operator or attempt script), levels held by the runtime until acted upon.
inline constexpr std::uint32_t request_take_off = 1u << 18;
inline constexpr std::uint32_t request_throw = 1u << 19;
inline constexpr std::uint32_t request_catch = 1u << 20;
inline constexpr std::uint32_t request_abort = 1u << 21;
inline constexpr std::uint32_t request_land = 1u << 22;
// The pole on this plate tilted beyond what balancing recovers from (after the requests so that
// the bits logged before it keep their numbers).
inline constexpr std::uint32_t pole_fallen = 1u << 23;
inline constexpr int kCount = 24;
}  // namespace condition
std::string_view condition_name(int bit);
// The bits of a condition word by name, "vehicle_lost|armed", or "0" (for logs and tests).
std::string condition_names(std::uint32_t word);

enum class Reason : std::uint8_t {
  none,
  vehicle_lost,
  estimate_lost,
  vehicle_back,
  land_requested,
  landed,
  take_off_requested,
  armed,
  arm_failed,
  airborne,
  pole_placed,
  pole_lost,
  throw_requested,
  throw_ended,
  pole_left_early,
  released,
  clear_of_pole,
  catch_requested,
  catch_started,
  out_of_reach,
  infeasible,
  abort_requested,
  caught,
  missed,
  pole_upright,
  pole_down,
  pole_fallen,
  near_floor,  // the descent reached its hand-over height
};
std::string_view reason_name(Reason reason);

using Transition = TableRow<Task, Reason>;  // from: a TaskSet

namespace c = condition;
// Ordered by severity; the first row that matches the current task wins.
inline constexpr std::array kTransitions = {
    // Losing the vehicle or its estimate: stop commanding it; the firmware's failsafe takes over.
    Transition{kAirborne | tasks(Task::landing), c::vehicle_lost, 0, Task::failsafe, Reason::vehicle_lost},
    Transition{kAirborne, c::estimate_lost, 0, Task::failsafe, Reason::estimate_lost},
    Transition{tasks(Task::failsafe, Task::landing), c::on_ground, c::vehicle_lost | c::armed, Task::parked,
               Reason::landed},
    Transition{tasks(Task::parked), c::armed, c::vehicle_lost | c::on_ground | c::estimate_lost, Task::hover,
               Reason::vehicle_back},
    // The operator's land, then abort. The ground station flies the vehicle down on motion capture
    // and hands it the last few centimetres: the firmware's own descent holds its attitude from the
    // gyro alone, whose drift after minutes of flight tilts it by degrees (measured: a vehicle
    // landing from 2 m after 30 throws drifted 33 m in 20 s and sank 0.6 m).
    Transition{kAirborne & ~tasks(Task::descend), c::request_land, 0, Task::descend, Reason::land_requested},
    Transition{tasks(Task::descend), c::at_target, 0, Task::landing, Reason::near_floor},
    Transition{tasks(Task::throwing), c::request_abort, 0, Task::release, Reason::abort_requested},
    Transition{tasks(Task::wait, Task::catching), c::request_abort, 0, Task::clear, Reason::abort_requested},
    // Take-off.
    Transition{tasks(Task::parked), c::request_take_off, c::vehicle_lost | c::estimate_lost, Task::arming,
               Reason::take_off_requested},
    Transition{tasks(Task::arming), c::command_failed, 0, Task::parked, Reason::arm_failed},
    Transition{tasks(Task::arming), c::armed, c::vehicle_lost | c::estimate_lost, Task::take_off,
               Reason::armed},
    Transition{tasks(Task::take_off), c::at_height, 0, Task::hover, Reason::airborne},
    // The pole on the plate: balance it; dropped: back to hover.
    // A pole fallen over on the plate is lost too: the vehicle levels in hover while it slides off
    // rather than chase it (the tilt it would need rolls the vehicle over), and balances a pole
    // only once it is upright.
    Transition{tasks(Task::hover), c::pole_on_self | c::pole_upright, 0, Task::balance, Reason::pole_placed},
    Transition{tasks(Task::balance), 0, c::pole_on_self, Task::hover, Reason::pole_lost},
    Transition{tasks(Task::balance), c::pole_on_self | c::pole_fallen, 0, Task::hover, Reason::pole_fallen},
    // The throw.
    Transition{tasks(Task::balance), c::request_throw | c::settled, 0, Task::throwing,
               Reason::throw_requested},
    Transition{tasks(Task::throwing), c::throw_over, 0, Task::release, Reason::throw_ended},
    Transition{tasks(Task::throwing), 0, c::pole_on_self, Task::release, Reason::pole_left_early},
    Transition{tasks(Task::release), c::release_over, 0, Task::retreat, Reason::released},
    Transition{tasks(Task::retreat), c::at_target, 0, Task::hover, Reason::clear_of_pole},
    // The catch.
    Transition{tasks(Task::hover), c::request_catch, c::pole_on_self, Task::wait, Reason::catch_requested},
    Transition{tasks(Task::wait, Task::catching), c::catch_unreachable, c::pole_on_self, Task::clear,
               Reason::out_of_reach},
    Transition{tasks(Task::wait, Task::catching), c::catch_infeasible, c::pole_on_self, Task::clear,
               Reason::infeasible},
    Transition{tasks(Task::wait, Task::catching), c::pole_on_self, 0, Task::rebalance, Reason::caught},
    Transition{tasks(Task::wait, Task::catching), c::pole_down, 0, Task::hover, Reason::pole_down},
    Transition{tasks(Task::catching), c::catch_missed, 0, Task::clear, Reason::missed},
    Transition{tasks(Task::wait), c::catch_due, 0, Task::catching, Reason::catch_started},
    Transition{tasks(Task::wait), 0, c::request_catch, Task::hover, Reason::abort_requested},
    Transition{tasks(Task::rebalance), c::pole_upright, c::pole_free | c::pole_down, Task::balance,
               Reason::pole_upright},
    Transition{tasks(Task::rebalance), 0, c::pole_on_self, Task::clear, Reason::pole_lost},
    Transition{tasks(Task::clear), c::pole_down, 0, Task::hover, Reason::pole_down},
    Transition{tasks(Task::clear), c::settled, c::pole_free, Task::hover, Reason::clear_of_pole},
};

// The first row of kTransitions that matches `task` under `conditions`, or nullptr.
const Transition* find_transition(Task task, std::uint32_t conditions);

// One vehicle's sequencer: its task, since when, and the last transition taken.
class VehicleSequencer {
 public:
  Task task() const { return task_; }
  double task_since_s() const { return since_s_; }
  Reason last_reason() const { return reason_; }
  std::uint32_t last_conditions() const { return conditions_; }

  // At most one transition; true if the task changed.
  bool step(std::uint32_t conditions, double now_s);
  // Forces a task (the runtime's start from a known state, e.g. re-attaching to a vehicle that
  // already flies).
  void reset(Task task, double now_s);

 private:
  Task task_ = Task::parked;
  double since_s_ = 0.0;
  Reason reason_ = Reason::none;
  std::uint32_t conditions_ = 0;
};

}  // namespace gs::mission
