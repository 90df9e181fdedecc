#include "fw/command_link.hpp"

#include "pa/sequence.hpp"

namespace fw {

using namespace pa::proto;

CommandLink::CommandLink(const LinkConfig& link, const SupervisorConfig& supervisor)
    : node_(link.vehicle.node()),
      setpoint_timeout_us_(supervisor.setpoint_timeout_us),
      heartbeat_timeout_us_(supervisor.heartbeat_timeout_us) {}

void CommandLink::on_frame(const Frame& frame, std::uint32_t now_us) {
  Message m;
  const DecodeStatus status = decode(frame, m);
  if (status != DecodeStatus::ok) {
    counters_.count(status);
    return;
  }
  on_message(m, now_us);
}

void CommandLink::on_message(const Message& m, std::uint32_t now_us) {
  // Frames for other nodes share the bus; they are neither ours nor errors.
  if (m.node != node_ && m.node != kBroadcastNode) return;
  apply(m, now_us);
}

void CommandLink::apply(const Message& m, std::uint32_t now_us) {
  switch (m.type) {
    case Type::kill:
      // Always honoured, whatever the session: the operator's last resort.
      kill_pending_ = true;
      kill_reason_ = m.kill.reason;
      break;
    case Type::command:
      if (!commands_.push(m.command)) {
        RxCounters::bump(counters_.queue_full);  // the ground retries an unacknowledged command
        return;
      }
      break;
    case Type::rate_thrust:
      // Only a new sequence number refreshes the stream; repeats and replays are stale.
      if (has_setpoint_ && !pa::SetpointSeq::is_newer(m.rate_thrust.seq, setpoint_.seq)) {
        RxCounters::bump(counters_.stale_sequence);
        return;
      }
      setpoint_ = m.rate_thrust;
      has_setpoint_ = true;
      setpoint_us_ = now_us;
      break;
    case Type::gs_heartbeat: {
      const GsHeartbeat& hb = m.gs_heartbeat;
      if (may_rebind_ && (!has_session_ || hb.session_token != session_token_)) {
        session_token_ = hb.session_token;
        has_session_ = true;
        has_heartbeat_ = false;  // a new session starts its own sequence
      }
      if (hb.session_token != session_token_) {
        RxCounters::bump(counters_.foreign_session);
        return;
      }
      if (has_heartbeat_ && !pa::HeartbeatSeq::is_newer(hb.seq, heartbeat_seq_)) {
        RxCounters::bump(counters_.stale_sequence);
        return;
      }
      has_heartbeat_ = true;
      heartbeat_seq_ = hb.seq;
      heartbeat_us_ = now_us;
      break;
    }
    case Type::timesync_request:
      timesync_pending_ = true;
      timesync_ = m.timesync_request;
      timesync_rx_us_ = now_us;
      break;
    default:
      // Vehicle-to-ground and plant frames are never addressed to the vehicle's link.
      RxCounters::bump(counters_.wrong_direction);
      return;
  }
  RxCounters::bump(counters_.accepted);
}

std::uint32_t CommandLink::setpoint_age_us(std::uint32_t now_us) const {
  if (!has_setpoint_) return 0xFFFFFFFFu;
  const std::int32_t age = pa::elapsed_us(now_us, setpoint_us_);
  return age < 0 ? 0u : static_cast<std::uint32_t>(age);
}

}  // namespace fw
