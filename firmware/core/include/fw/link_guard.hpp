// The vehicle's end of the authenticated link (pa/link_auth.hpp): it stands in front of the
// command link and lets through only ground frames whose AUTH tag verifies under this boot's
// session key with a counter above the last accepted one. Everything else is counted and
// dropped; no frame is acted on before it is verified, KILL included (a forged KILL would
// otherwise drop a vehicle out of the sky).
//
// Receiving costs a copy of the frame and its decoding (the port does it between ticks). The
// MAC is computed in the ticks, one frame per three ticks (pa::auth::TagCheck's steps), so the
// longest tick stays bounded whatever arrives, and a frame is acted on in the third tick after it
// arrived. Frames with their AUTH wait in a queue of four (at 260 per second per vehicle, one
// arrives every ~4 ticks).
#pragma once

#include <cstdint>

#include "fw/config.hpp"
#include "fw/fixed_queue.hpp"
#include "fw/saturating.hpp"
#include "pa/link_auth.hpp"
#include "pa/protocol.hpp"

namespace fw {

class LinkGuard {
 public:
  static constexpr std::size_t kQueue = 4;

  explicit LinkGuard(const LinkConfig& link);

  // A decoded ground-to-vehicle frame addressed to this vehicle, then its AUTH (the caller routes).
  void on_frame(const pa::proto::Frame& frame, const pa::proto::Message& decoded, std::uint32_t received_us);
  void on_auth(const pa::proto::Frame& auth);
  // A ground frame no AUTH can vouch for (a broadcast): counted as forged.
  void on_unsigned() { saturating_increment(forged_); }
  // Once per tick: the next step of the check of one queued frame (the oldest, or the latest
  // KILL, which supersedes what came before it); true, with the decoded frame in `out`, when a
  // check completes and holds, and when it was received in `received_us` (a setpoint is fresh
  // from its arrival, not from the end of its check).
  bool verify_next(pa::proto::Message& out, std::uint32_t& received_us);

  std::size_t queued() const { return queue_.size(); }  // frames with their AUTH, not yet verified
  std::uint32_t nonce() const { return nonce_; }
  std::uint32_t last_counter() const { return last_counter_; }
  bool provisioned() const { return provisioned_; }
  std::uint32_t forged() const { return forged_; }
  std::uint32_t replayed() const { return replayed_; }
  std::uint32_t queue_full() const { return queue_full_; }
  std::uint32_t rejected() const { return forged_ + replayed_ + queue_full_; }

 private:
  // A frame with its AUTH, prepared on arrival so that the ticks only run the MAC.
  struct Pending {
    pa::proto::Message message;
    pa::auth::TagCheck::Words words;
    std::uint64_t tag;
    std::uint32_t received_us;
    std::uint16_t counter_low;
  };
  void start_check();  // of the head (a KILL moved there first): the counter, the first step
  void drop_head();
  void drop(std::size_t n);  // the first n queued frames
  bool finish_check(pa::proto::Message& out, std::uint32_t& received_us);

  pa::auth::TagCheck check_{};
  std::uint32_t nonce_;
  bool provisioned_;
  std::uint32_t last_counter_ = 0;  // counters start at 1

  Pending held_{};  // the latest frame still waiting for its AUTH
  bool holding_ = false;
  FixedQueue<Pending, kQueue> queue_{};

  // The check in progress: its next step (0: none in progress).
  int step_ = 0;  // the head of the queue is being checked while it is not 0
  std::uint32_t counter_ = 0;
  std::size_t superseded_ = 0;   // frames behind the KILL at the head that were queued before it
  std::size_t latest_kill_ = 0;  // 1 + the queue position of the latest KILL, 0: none queued

  std::uint32_t forged_ = 0;
  std::uint32_t replayed_ = 0;
  std::uint32_t queue_full_ = 0;
};

}  // namespace fw
