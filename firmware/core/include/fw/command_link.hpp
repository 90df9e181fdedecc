// The vehicle's end of the compact protocol: decodes every received frame, keeps the
// setpoint stream and ground heartbeat watchdogs, queues commands for the supervisor, and
// buffers the frames the vehicle sends. Malformed frames are counted and dropped; nothing
// here asserts, allocates or loops over unbounded input.
#pragma once

#include <cstdint>

#include "fw/config.hpp"
#include "fw/fixed_queue.hpp"
#include "fw/saturating.hpp"
#include "pa/protocol.hpp"
#include "pa/sequence.hpp"

namespace fw {

class CommandLink {
 public:
  static constexpr std::size_t kCommandQueue = 4;
  static constexpr std::size_t kTxQueue = 32;

  CommandLink(const LinkConfig& link, const SupervisorConfig& supervisor);

  // Decode and apply one received frame; `now_us` is the vehicle clock when it was read.
  void on_frame(const pa::proto::Frame& frame, std::uint32_t now_us);
  // Apply one decoded frame (the vehicle's link guard has verified it).
  void on_message(const pa::proto::Message& message, std::uint32_t now_us);

  // A setpoint with a new sequence number arrived within the stale timeout. A stream that
  // repeats an old sequence does not refresh this, however often it arrives.
  bool setpoint_fresh(std::uint32_t now_us) const {
    return has_setpoint_ &&
           pa::elapsed_us(now_us, setpoint_us_) <= static_cast<std::int32_t>(setpoint_timeout_us_);
  }
  // The latest accepted setpoint (zero thrust and rates before the first one).
  const pa::proto::RateThrust& setpoint() const { return setpoint_; }
  std::uint32_t setpoint_age_us(std::uint32_t now_us) const;

  // Ground heartbeats with advancing sequence numbers and the bound session token.
  bool heartbeat_live(std::uint32_t now_us) const {
    return has_heartbeat_ &&
           pa::elapsed_us(now_us, heartbeat_us_) <= static_cast<std::int32_t>(heartbeat_timeout_us_);
  }
  // The ground station's session: adopted from heartbeats while `may_rebind` is true
  // (the vehicle is on the ground, motors off), fixed otherwise so a second ground station cannot
  // take over a vehicle in the air.
  void set_session_rebind(bool may_rebind) { may_rebind_ = may_rebind; }
  std::uint16_t session_token() const { return session_token_; }
  bool has_session() const { return has_session_; }

  // KILL is latched until taken, whatever its token. (These are asked every tick and nearly
  // always answer no, so the question is inline.)
  bool take_kill(pa::proto::KillReason& reason) {
    if (!kill_pending_) return false;
    kill_pending_ = false;
    reason = kill_reason_;
    return true;
  }
  bool take_command(pa::proto::Command& out) { return commands_.pop(out); }
  bool command_waiting() const { return !commands_.empty(); }
  bool take_timesync(pa::proto::TimesyncRequest& request, std::uint32_t& received_us) {
    if (!timesync_pending_) return false;
    timesync_pending_ = false;
    request = timesync_;
    received_us = timesync_rx_us_;
    return true;
  }

  // A full queue drops the new frame and counts it; the caller decides what matters more by what
  // it sends first.
  bool send(const pa::proto::Frame& f) {
    if (tx_.push(f)) return true;
    saturating_increment(tx_dropped_);
    return false;
  }
  // encode() then send(), with the frame encoded straight into the transmit queue: nothing is
  // sent when the message does not encode, and a full queue drops (and counts) it.
  template <class Message>
  bool send_message(const Message& message) {
    pa::proto::Frame* slot = tx_.next_slot();
    if (slot == nullptr) {
      pa::proto::Frame f;
      if (encode(message, node_, f)) saturating_increment(tx_dropped_);
      return false;
    }
    if (!encode(message, node_, *slot)) return false;  // encode() leaves the slot alone then
    tx_.commit();
    return true;
  }
  bool pop_tx(pa::proto::Frame& out) { return tx_.pop(out); }
  std::uint32_t tx_dropped() const { return tx_dropped_; }

  const pa::proto::RxCounters& counters() const { return counters_; }
  std::uint8_t node() const { return node_; }

 private:
  void apply(const pa::proto::Message& m, std::uint32_t now_us);

  std::uint8_t node_;
  std::uint32_t setpoint_timeout_us_;
  std::uint32_t heartbeat_timeout_us_;

  pa::proto::RateThrust setpoint_{};
  bool has_setpoint_ = false;
  std::uint32_t setpoint_us_ = 0;

  bool has_heartbeat_ = false;
  std::uint8_t heartbeat_seq_ = 0;
  std::uint32_t heartbeat_us_ = 0;
  bool may_rebind_ = true;
  bool has_session_ = false;
  std::uint16_t session_token_ = 0;

  bool kill_pending_ = false;
  pa::proto::KillReason kill_reason_ = pa::proto::KillReason::operator_request;

  FixedQueue<pa::proto::Command, kCommandQueue> commands_{};

  bool timesync_pending_ = false;
  pa::proto::TimesyncRequest timesync_{};
  std::uint32_t timesync_rx_us_ = 0;

  pa::proto::RxCounters counters_{};
  FixedQueue<pa::proto::Frame, kTxQueue> tx_{};
  std::uint32_t tx_dropped_ = 0;
};

}  // namespace fw
