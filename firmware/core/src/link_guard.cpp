#include "fw/link_guard.hpp"

namespace fw {

using namespace pa::proto;

LinkGuard::LinkGuard(const LinkConfig& link)
    : nonce_(link.session_nonce), provisioned_(pa::auth::provisioned(link.key)) {
  if (provisioned_) check_ = pa::auth::TagCheck(pa::auth::session_key(link.key, nonce_));
}

void LinkGuard::on_frame(const Frame& frame, const Message& decoded, std::uint32_t received_us) {
  if (holding_) saturating_increment(forged_);  // its AUTH never came
  held_.message = decoded;
  held_.received_us = received_us;
  held_.words = pa::auth::TagCheck::words(frame);
  holding_ = true;
}

void LinkGuard::on_auth(const Frame& frame) {
  if (!holding_) {
    saturating_increment(forged_);  // an AUTH with nothing to vouch for
    return;
  }
  holding_ = false;
  if (queue_.full()) {
    saturating_increment(queue_full_);
    // A KILL is never the one dropped: it takes the newest entry's place (the head, which may
    // be under check, is never the newest of a full queue), so a flood cannot keep it out.
    if (held_.message.type != Type::kill) return;
    queue_.pop_back();
    latest_kill_ = latest_kill_ > queue_.size() ? 0 : latest_kill_;
  }
  // AUTH: u16 counter low bits, then the 48-bit tag (the caller checked type and length).
  const std::uint64_t auth = pa::auth::detail::load_u64(frame.data.data());
  held_.counter_low = static_cast<std::uint16_t>(auth);
  held_.tag = auth >> 16;
  queue_.push(held_);
  if (held_.message.type == Type::kill) latest_kill_ = queue_.size();
}

bool LinkGuard::verify_next(Message& out, std::uint32_t& received_us) {
  switch (step_) {
    case 1:
      check_.advance();
      step_ = 2;
      return false;
    case 2: return finish_check(out, received_us);
    default:
      // Start the next check. Replays cost no MAC, so they are skipped here (at most the queue).
      while (!queue_.empty() && step_ == 0) start_check();
      return false;
  }
}

void LinkGuard::start_check() {
  // A KILL waits for nothing: the latest queued one goes first (moved to the head). If it
  // verifies, the frames before it are superseded (motors off makes an earlier setpoint or
  // command moot, and their counters are below the KILL's, so they could no longer be accepted
  // anyway); if not, only it goes.
  superseded_ = latest_kill_ > 1 ? latest_kill_ - 1 : 0;
  latest_kill_ = 0;
  if (superseded_ != 0) {
    const Pending kill = queue_[superseded_];
    for (std::size_t k = superseded_; k > 0; --k) queue_[k] = queue_[k - 1];
    queue_.front() = kill;
  }
  const Pending& p = queue_.front();
  if (!provisioned_) {
    saturating_increment(forged_);
    drop_head();
    return;
  }
  // The counter first: a replay is refused without spending a MAC on it.
  if (pa::auth::expand_counter(last_counter_, p.counter_low, counter_) != pa::auth::CounterCheck::fresh) {
    saturating_increment(replayed_);
    drop_head();
    return;
  }
  check_.start(counter_, p.words, p.tag);
  step_ = 1;
}

void LinkGuard::drop_head() { drop(1); }

void LinkGuard::drop(std::size_t n) {
  queue_.pop_front(n);
  latest_kill_ = latest_kill_ > n ? latest_kill_ - n : 0;
}

bool LinkGuard::finish_check(Message& out, std::uint32_t& received_us) {
  step_ = 0;
  const bool ok = check_.finish();
  if (!ok) {
    saturating_increment(forged_);  // a forged KILL supersedes nothing: the frames behind it keep their turn
  } else {
    last_counter_ = counter_;
    out = queue_.front().message;
    received_us = queue_.front().received_us;
  }
  drop(ok ? 1 + superseded_ : 1);
  superseded_ = 0;
  return ok;
}

}  // namespace fw
