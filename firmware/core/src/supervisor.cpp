#include "fw/supervisor.hpp"

#include <cmath>

#include "pa/sequence.hpp"

namespace fw {

using pa::proto::CommandCode;
using pa::proto::FailsafeReason;
using pa::proto::Mode;
using pa::proto::RefuseReason;

namespace {

bool at_least(std::uint32_t elapsed_us, std::uint32_t limit_us) { return elapsed_us >= limit_us; }

}  // namespace

std::uint32_t Supervisor::time_in_mode_us(std::uint32_t now_us) const {
  const std::int32_t t = pa::elapsed_us(now_us, entered_us_);
  return t > 0 ? static_cast<std::uint32_t>(t) : 0u;
}

void Supervisor::enter(Mode mode, FailsafeReason reason, std::uint32_t now_us) {
  mode_ = mode;
  may_follow_new_session_ = mode == Mode::disarmed || mode == Mode::landed;
  time_limit_us_ = mode_time_limit_us(mode, config_);
  reason_ = reason;
  entered_us_ = now_us;
}

void Supervisor::update(const SupervisorInputs& in) {
  // One bad IMU sample is a glitch; imu_timeout_us of them is a lost IMU, until a good one.
  if (in.imu_ok) {
    imu_unhealthy_ = false;
    imu_lost_ = false;
  } else if (!imu_unhealthy_) {
    imu_unhealthy_ = true;
    imu_unhealthy_since_us_ = in.now_us;
  }
  if (imu_unhealthy_ && !imu_lost_) {
    const std::int32_t unhealthy_us = pa::elapsed_us(in.now_us, imu_unhealthy_since_us_);
    imu_lost_ =
        unhealthy_us >= 0 && at_least(static_cast<std::uint32_t>(unhealthy_us), config_.imu_timeout_us);
  }
  const bool imu_lost = imu_lost_;

  // The time in a mode saturates (about 18 minutes) so that the wrap-safe clock difference
  // never wraps while update() runs.
  if (pa::elapsed_us(in.now_us, entered_us_) > kTimeInModeMax_us)
    entered_us_ = in.now_us - static_cast<std::uint32_t>(kTimeInModeMax_us);
  const std::uint32_t in_mode_us = time_in_mode_us(in.now_us);
  std::uint16_t c = 0;
  if (in.heartbeat_live) c |= condition::heartbeat_live;
  if (in.setpoint_fresh) c |= condition::setpoint_fresh;
  if (in.setpoint_fresh && std::isfinite(in.setpoint_thrust_mps2) &&
      in.setpoint_thrust_mps2 > config_.takeoff_thrust_mps2)
    c |= condition::takeoff_thrust;
  if (imu_lost) c |= condition::imu_lost;
  if (in.on_ground) c |= condition::on_ground;
  if (in.crash) c |= condition::crash;
  if (at_least(in_mode_us, time_limit_us_)) c |= condition::mode_timeout;
  if (reason_ == FailsafeReason::land_command) c |= condition::land_commanded;
  conditions_ = c;

  // The table is a function of the mode and the conditions only: a pair that matched no row
  // before matches none now, which spares the scan on the steady ticks.
  if (mode_ == unmatched_mode_ && c == unmatched_conditions_) return;
  const std::size_t i = find_transition(mode_, c);
  if (i == kSupervisorTransitions.size()) {
    unmatched_mode_ = mode_;
    unmatched_conditions_ = c;
    return;
  }
  const SupervisorTransition& row = kSupervisorTransitions[i];
  enter(row.to, row.keep_reason ? reason_ : row.reason, in.now_us);
}

CommandResult Supervisor::handle_command(CommandCode code, const SupervisorInputs& now) {
  const auto refuse = [](RefuseReason r) { return CommandResult{false, r}; };
  const CommandResult accepted{true, RefuseReason::none};
  switch (code) {
    case CommandCode::arm:
      // The explicit disarmed -> armed edge: never from any other mode, never with thrust asked for.
      if (mode_ == Mode::killed) return refuse(RefuseReason::killed);
      if (mode_ != Mode::disarmed) return refuse(RefuseReason::not_disarmed);
      if (!now.heartbeat_live) return refuse(RefuseReason::no_ground_heartbeat);
      if (!(std::isfinite(now.setpoint_thrust_mps2) &&
            now.setpoint_thrust_mps2 <= config_.arming_thrust_max_mps2))
        return refuse(RefuseReason::thrust_not_zero);
      if (!now.imu_ok) return refuse(RefuseReason::imu_unhealthy);
      enter(Mode::armed, FailsafeReason::none, now.now_us);
      return accepted;

    case CommandCode::disarm:
      switch (mode_) {
        case Mode::disarmed:
        case Mode::armed:
        case Mode::landed:
        case Mode::killed: enter(Mode::disarmed, FailsafeReason::none, now.now_us); return accepted;
        case Mode::flying:
        case Mode::hold:
        case Mode::failsafe_hover:
        case Mode::failsafe_descent:
          return refuse(RefuseReason::not_disarmed);  // not in the air: LAND or KILL
      }
      return refuse(RefuseReason::not_disarmed);

    case CommandCode::land:
      switch (mode_) {
        case Mode::flying:
        case Mode::hold:
        case Mode::failsafe_hover:
          enter(Mode::failsafe_descent, FailsafeReason::land_command, now.now_us);
          return accepted;
        case Mode::failsafe_descent:
          reason_ = FailsafeReason::land_command;  // already descending: now it ends only on the ground
          return accepted;
        case Mode::killed: return refuse(RefuseReason::killed);
        case Mode::disarmed:
        case Mode::armed:
        case Mode::landed: return refuse(RefuseReason::not_flying);
      }
      return refuse(RefuseReason::not_flying);

    case CommandCode::expect_catch:
    case CommandCode::catch_handled:
    case CommandCode::set_motor_time_constant:
    case CommandCode::set_inertia_scale:
    case CommandCode::correct_tilt: break;
  }
  return refuse(RefuseReason::bad_argument);
}

void Supervisor::kill(std::uint32_t now_us) { enter(Mode::killed, FailsafeReason::kill, now_us); }

}  // namespace fw
