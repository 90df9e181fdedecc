// Supervisor: arming, failsafes and KILL, as a table-driven state machine over the vehicle
// modes of the protocol (pa::proto::Mode).
//
// Shape (after Crazyflie's supervisor_state_machine.c): every update() turns its inputs into a
// word of condition bits; the constexpr table kSupervisorTransitions lists, in order, the rows
// "from mode M, when all of these bits hold and none of those, go to mode N with reason R";
// the first row of the current mode that matches wins, at most one transition per update.
// Modes without rows (disarmed, landed, killed) only leave by a command.
//
// Commands are edges, not levels, so they are not table rows: handle_command() checks the
// preconditions of ARM, DISARM and LAND and answers with the protocol's refuse reason; kill()
// is always honoured. The caller (the vehicle composition) owns the link and the detectors and
// computes the inputs each tick; action() tells it what to fly without knowing the table.
//
// Choices the issue left open, and why:
// - IMU lost in the air (imu_ok false for imu_timeout_us): motors off (killed, reason imu_lost).
//   Without rates and attitude neither the levelled hover nor the descent can be flown; thrust
//   on a vehicle that tumbles accelerates it in an arbitrary direction, which is worse next to
//   the other vehicle and the pole than a drop. A single bad sample does not count: the IMU is
//   lost only after imu_timeout_us of unhealthy samples. On the ground (armed) it disarms.
// - A crash reported by the impact detector while the motors run: motors off (killed, reason
//   crash), as Crazyflie does on a tumble; the rotors of a vehicle that hit something are the
//   danger.
// - DISARM in the air is refused (PX4 style: the operator uses LAND, or KILL). The protocol has
//   no "in flight" refuse reason; the answer is not_disarmed and the COMMAND_ACK's mode shows why.
// - LAND while already in a failsafe descent is accepted and turns it into a commanded landing
//   (it no longer ends when the stream resumes); its timeout keeps running.
// - A stale setpoint stream is first a hold, not a failsafe: the vehicle levels and hovers on
//   board within setpoint_timeout_us (the 25 ms a dead ground station allows) and flies the
//   stream again at its next fresh setpoint. A radio that fades for 100 ms, which an arena's radio
//   does, so costs a levelled hover that short and nothing more: no failsafe reason, nothing for
//   the ground station to recover. Only a hold past hold_max_us, or a ground heartbeat silent for
//   heartbeat_timeout_us, is the failsafe hover, which descends after hover_before_descent_us.
// - A failsafe ends (back to flying) when the ground station retakes control: a fresh setpoint
//   stream and a live heartbeat together. A commanded landing only ends on the ground.
// - Landed keeps the reason that led there and the motors off until DISARM: re-arming needs
//   the DISARM -> ARM edge again.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "fw/config.hpp"
#include "pa/protocol.hpp"

namespace fw {

// What the caller computes once per tick.
struct SupervisorInputs {
  std::uint32_t now_us = 0;
  bool heartbeat_live = false;        // ground heartbeats arriving within the timeout
  bool setpoint_fresh = false;        // a new-sequence setpoint within setpoint_timeout_us
  float setpoint_thrust_mps2 = 0.0f;  // the latest accepted collective thrust setpoint
  bool imu_ok = false;                // this tick's IMU sample is healthy
  bool on_ground = false;             // the landing detector: the floor carries the vehicle
  bool crash = false;                 // the impact detector reported a crash this tick
};

// What to fly. The failsafe actions are ordered by severity (PX4 style): automatic
// transitions only ever move to a more severe action, except the recovery to track_setpoints
// when the ground station retakes control. idle is the armed vehicle waiting on the ground.
enum class Action : std::uint8_t {
  idle = 0,             // armed on the ground: motors at idle, no control
  track_setpoints = 1,  // fly the ground station's rate and thrust setpoints
  level_hover = 2,      // hold level and height on board (a hold, or the failsafe hover)
  descend = 3,          // level, sink at descent_rate_mps until the ground
  motors_off = 4,       // disarmed, landed or killed
};

constexpr Action action_for(pa::proto::Mode mode) {
  switch (mode) {
    case pa::proto::Mode::armed: return Action::idle;
    case pa::proto::Mode::flying: return Action::track_setpoints;
    case pa::proto::Mode::hold:
    case pa::proto::Mode::failsafe_hover: return Action::level_hover;
    case pa::proto::Mode::failsafe_descent: return Action::descend;
    case pa::proto::Mode::disarmed:
    case pa::proto::Mode::landed:
    case pa::proto::Mode::killed: return Action::motors_off;
  }
  return Action::motors_off;
}

// Flown on the vehicle's own estimate, without the ground station: a hold or a failsafe.
constexpr bool on_board_flight(pa::proto::Mode mode) {
  return action_for(mode) == Action::level_hover || action_for(mode) == Action::descend;
}

// The condition bits a transition row tests.
namespace condition {
inline constexpr std::uint16_t heartbeat_live = 1u << 0;
inline constexpr std::uint16_t setpoint_fresh = 1u << 1;
// the setpoint is fresh and above takeoff_thrust_mps2
inline constexpr std::uint16_t takeoff_thrust = 1u << 2;
inline constexpr std::uint16_t imu_lost = 1u << 3;  // IMU unhealthy for imu_timeout_us
inline constexpr std::uint16_t on_ground = 1u << 4;
inline constexpr std::uint16_t crash = 1u << 5;
// time in the mode >= its time limit: hold_max_us in a hold, hover_before_descent_us in the
// failsafe hover, descent_max_us in the descent (mode_time_limit_us; the other modes have none)
inline constexpr std::uint16_t mode_timeout = 1u << 6;
inline constexpr std::uint16_t land_commanded = 1u << 7;  // the current failsafe is a LAND command
inline constexpr unsigned kCount = 8;
inline constexpr std::uint16_t kAll = (1u << kCount) - 1u;
}  // namespace condition

struct SupervisorTransition {
  pa::proto::Mode from;
  std::uint16_t all_of;   // every one of these conditions holds ...
  std::uint16_t none_of;  // ... and none of these
  pa::proto::Mode to;
  pa::proto::FailsafeReason reason;  // recorded on entry ...
  bool keep_reason;                  // ... unless the row escalates and keeps the original cause
};

// The transition table. Within each mode the rows are in priority order: crash, IMU, then the
// link, recovery, ground contact and timers.
inline constexpr std::array<SupervisorTransition, 23> kSupervisorTransitions{{
    // armed: on the ground, motors idle, waiting for a take-off setpoint
    {pa::proto::Mode::armed, condition::crash, 0, pa::proto::Mode::killed, pa::proto::FailsafeReason::crash,
     false},
    {pa::proto::Mode::armed, condition::imu_lost, 0, pa::proto::Mode::disarmed,
     pa::proto::FailsafeReason::imu_lost, false},
    {pa::proto::Mode::armed, 0, condition::heartbeat_live, pa::proto::Mode::disarmed,
     pa::proto::FailsafeReason::heartbeat_lost, false},
    {pa::proto::Mode::armed, condition::setpoint_fresh | condition::takeoff_thrust, 0,
     pa::proto::Mode::flying, pa::proto::FailsafeReason::none, false},
    // flying: tracking the ground station's setpoints
    {pa::proto::Mode::flying, condition::crash, 0, pa::proto::Mode::killed, pa::proto::FailsafeReason::crash,
     false},
    {pa::proto::Mode::flying, condition::imu_lost, 0, pa::proto::Mode::killed,
     pa::proto::FailsafeReason::imu_lost, false},
    {pa::proto::Mode::flying, 0, condition::heartbeat_live, pa::proto::Mode::failsafe_hover,
     pa::proto::FailsafeReason::heartbeat_lost, false},
    {pa::proto::Mode::flying, 0, condition::setpoint_fresh, pa::proto::Mode::hold,
     pa::proto::FailsafeReason::none, false},
    // failsafe_hover: levelled hover, then a descent
    {pa::proto::Mode::failsafe_hover, condition::crash, 0, pa::proto::Mode::killed,
     pa::proto::FailsafeReason::crash, false},
    {pa::proto::Mode::failsafe_hover, condition::imu_lost, 0, pa::proto::Mode::killed,
     pa::proto::FailsafeReason::imu_lost, false},
    {pa::proto::Mode::failsafe_hover, condition::setpoint_fresh | condition::heartbeat_live, 0,
     pa::proto::Mode::flying, pa::proto::FailsafeReason::none, false},
    {pa::proto::Mode::failsafe_hover, condition::on_ground, 0, pa::proto::Mode::landed,
     pa::proto::FailsafeReason::none, true},
    {pa::proto::Mode::failsafe_hover, condition::mode_timeout, 0, pa::proto::Mode::failsafe_descent,
     pa::proto::FailsafeReason::none, true},
    // failsafe_descent: levelled descent until the floor holds the vehicle
    {pa::proto::Mode::failsafe_descent, condition::crash, 0, pa::proto::Mode::killed,
     pa::proto::FailsafeReason::crash, false},
    {pa::proto::Mode::failsafe_descent, condition::imu_lost, 0, pa::proto::Mode::killed,
     pa::proto::FailsafeReason::imu_lost, false},
    {pa::proto::Mode::failsafe_descent, condition::on_ground, 0, pa::proto::Mode::landed,
     pa::proto::FailsafeReason::none, true},
    {pa::proto::Mode::failsafe_descent, condition::mode_timeout, 0, pa::proto::Mode::landed,
     pa::proto::FailsafeReason::none, true},
    {pa::proto::Mode::failsafe_descent, condition::setpoint_fresh | condition::heartbeat_live,
     condition::land_commanded, pa::proto::Mode::flying, pa::proto::FailsafeReason::none, false},
    // hold: the stream paused, levelled on board; the stream again, or a failsafe once it lasts
    {pa::proto::Mode::hold, condition::crash, 0, pa::proto::Mode::killed, pa::proto::FailsafeReason::crash,
     false},
    {pa::proto::Mode::hold, condition::imu_lost, 0, pa::proto::Mode::killed,
     pa::proto::FailsafeReason::imu_lost, false},
    {pa::proto::Mode::hold, 0, condition::heartbeat_live, pa::proto::Mode::failsafe_hover,
     pa::proto::FailsafeReason::heartbeat_lost, false},
    {pa::proto::Mode::hold, condition::setpoint_fresh, 0, pa::proto::Mode::flying,
     pa::proto::FailsafeReason::none, false},
    {pa::proto::Mode::hold, condition::mode_timeout, 0, pa::proto::Mode::failsafe_hover,
     pa::proto::FailsafeReason::setpoint_stale, false},
}};

// How long a mode may last before its mode_timeout row fires (none: never).
constexpr std::uint32_t mode_time_limit_us(pa::proto::Mode mode, const SupervisorConfig& config) {
  switch (mode) {
    case pa::proto::Mode::hold: return config.hold_max_us;
    case pa::proto::Mode::failsafe_hover: return config.hover_before_descent_us;
    case pa::proto::Mode::failsafe_descent: return config.descent_max_us;
    default: return 0xFFFFFFFFu;
  }
}

// Each mode's rows, [begin, end) in kSupervisorTransitions, so that an update scans only the
// rows of the current mode (in table order, so the first match still wins). Built from the
// table, which must keep each mode's rows together.
struct TransitionRows {
  std::uint8_t begin = 0;
  std::uint8_t end = 0;
};

constexpr std::array<TransitionRows, pa::proto::kModeMax + 1> make_transition_rows() {
  std::array<TransitionRows, pa::proto::kModeMax + 1> rows{};
  for (std::size_t i = kSupervisorTransitions.size(); i-- > 0;) {
    TransitionRows& r = rows[static_cast<std::size_t>(kSupervisorTransitions[i].from)];
    if (r.end == 0) r.end = static_cast<std::uint8_t>(i + 1);
    r.begin = static_cast<std::uint8_t>(i);
  }
  return rows;
}

inline constexpr std::array<TransitionRows, pa::proto::kModeMax + 1> kTransitionRows = make_transition_rows();

constexpr bool transition_rows_grouped() {
  std::size_t rows = 0;
  for (std::size_t m = 0; m < kTransitionRows.size(); ++m) {
    for (std::size_t i = kTransitionRows[m].begin; i < kTransitionRows[m].end; ++i)
      if (static_cast<std::size_t>(kSupervisorTransitions[i].from) != m) return false;
    rows += static_cast<std::size_t>(kTransitionRows[m].end - kTransitionRows[m].begin);
  }
  return rows == kSupervisorTransitions.size();
}
static_assert(kSupervisorTransitions.size() < 256, "row indices are bytes");
static_assert(transition_rows_grouped(), "each mode's transition rows must be consecutive in the table");

// The index of the first row for `from` that `conditions` satisfy, or kSupervisorTransitions.size().
constexpr std::size_t find_transition(pa::proto::Mode from, std::uint16_t conditions) {
  const auto mode = static_cast<std::size_t>(from);
  if (mode >= kTransitionRows.size()) return kSupervisorTransitions.size();
  for (std::size_t i = kTransitionRows[mode].begin; i < kTransitionRows[mode].end; ++i) {
    const SupervisorTransition& row = kSupervisorTransitions[i];
    if ((conditions & row.all_of) == row.all_of && (conditions & row.none_of) == 0) return i;
  }
  return kSupervisorTransitions.size();
}

struct CommandResult {
  bool accepted = false;
  pa::proto::RefuseReason reason = pa::proto::RefuseReason::none;  // why, when refused
};

class Supervisor {
 public:
  explicit Supervisor(const SupervisorConfig& config) : config_(config) {}

  // Evaluate the table once (call every tick, after the detectors).
  void update(const SupervisorInputs& in);

  // ARM: only from disarmed, with a live ground heartbeat, the setpoint thrust at or below
  //      arming_thrust_max_mps2 and a healthy IMU; refused with killed / not_disarmed /
  //      no_ground_heartbeat / thrust_not_zero / imu_unhealthy (checked in that order).
  // DISARM: from disarmed, armed, landed or killed (clears the KILL latch); refused in the air.
  // LAND: from flying, a hold or a failsafe -> failsafe_descent (reason land_command); refused with
  //      not_flying on the ground, killed when killed.
  // EXPECT_CATCH and CATCH_HANDLED are not the supervisor's: refused with bad_argument.
  CommandResult handle_command(pa::proto::CommandCode code, const SupervisorInputs& now);

  // KILL: motors off from any mode, latched until DISARM.
  void kill(std::uint32_t now_us);

  pa::proto::Mode mode() const { return mode_; }
  pa::proto::FailsafeReason reason() const { return reason_; }
  // Time since the mode was entered; saturates at kTimeInModeMax_us (about 18 minutes) while
  // update() runs, zero for a clock reading from before the entry.
  std::uint32_t time_in_mode_us(std::uint32_t now_us) const;
  static constexpr std::int32_t kTimeInModeMax_us = 1 << 30;
  Action action() const { return action_for(mode_); }
  bool motors_enabled() const { return action() != Action::motors_off; }  // armed, flying, failsafes
  // On the ground with the motors off and not killed (disarmed or landed): the modes in which the
  // vehicle may follow a new ground station's session. Kept at each mode change, so the 1 kHz
  // tick reads a flag rather than comparing modes.
  bool may_follow_new_session() const { return may_follow_new_session_; }
  std::uint16_t conditions() const { return conditions_; }  // the bits of the last update

 private:
  void enter(pa::proto::Mode mode, pa::proto::FailsafeReason reason, std::uint32_t now_us);

  SupervisorConfig config_;
  pa::proto::Mode mode_ = pa::proto::Mode::disarmed;
  bool may_follow_new_session_ = true;
  pa::proto::FailsafeReason reason_ = pa::proto::FailsafeReason::none;
  std::uint32_t entered_us_ = 0;
  std::uint32_t time_limit_us_ = 0xFFFFFFFFu;  // mode_time_limit_us() of the mode, kept at each change
  bool imu_unhealthy_ = false;
  bool imu_lost_ = false;
  std::uint32_t imu_unhealthy_since_us_ = 0;
  std::uint16_t conditions_ = 0;
  // The last mode and conditions that matched no row (0xFFFF: none yet, beyond condition::kAll).
  pa::proto::Mode unmatched_mode_ = pa::proto::Mode::disarmed;
  std::uint16_t unmatched_conditions_ = 0xFFFFu;
};

}  // namespace fw
