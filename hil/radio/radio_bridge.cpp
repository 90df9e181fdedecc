#include "hil/radio/radio_bridge.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hil {

RadioBridge::RadioBridge(const RadioConfig& config)
    : config_(config), rng_(config.seed), outages_(config.loss, config.outage_s) {
  if (!(std::isfinite(config.latency_s) && config.latency_s >= 0))
    throw std::invalid_argument("radio latency must be a finite, non-negative number of seconds");
  if (!(std::isfinite(config.jitter_s) && config.jitter_s >= 0))
    throw std::invalid_argument("radio jitter must be a finite, non-negative number of seconds");
  if (!(config.loss >= 0 && config.loss <= 1)) throw std::invalid_argument("radio loss must be within 0..1");
  if (!(std::isfinite(config.outage_s) && config.outage_s >= 0))
    throw std::invalid_argument("radio outage length must be a finite, non-negative number of seconds");
}

void RadioBridge::offer(Side from, const pa::proto::Frame& frame, double t_s) {
  Direction& d = dir(from);
  ++d.offered;
  const bool lost = losses_active_ && (config_.outage_s > 0.0 ? outages_.out(t_s, [&] { return unit_(rng_); })
                                                              : unit_(rng_) < config_.loss);
  if (lost) {
    ++d.lost;
    return;
  }
  const double due = std::max(d.last_due_s, t_s + config_.latency_s + config_.jitter_s * unit_(rng_));
  d.last_due_s = due;
  d.queue.push_back(InFlight{due, frame});
}

bool RadioBridge::deliver(Side to, double now_s, pa::proto::Frame& out) {
  // Frames for `to` travel in the direction that starts on the other side.
  Direction& d = dir(to == Side::ground ? Side::vehicle : Side::ground);
  if (d.queue.empty() || d.queue.front().due_s > now_s) return false;
  out = d.queue.front().frame;
  d.queue.pop_front();
  return true;
}

}  // namespace hil
