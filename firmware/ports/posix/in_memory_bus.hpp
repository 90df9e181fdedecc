// An in-memory CAN bus: every frame sent by one endpoint is delivered to every other endpoint,
// in order, as on a real bus. Fixed capacity, no heap: a full receive queue drops the frame and
// counts it, like a controller's overrun. Used to run the firmware core, the radio bridge and
// the ground station in one process (tests and the in-process simulation).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "fw/fixed_queue.hpp"
#include "fw/saturating.hpp"
#include "pa/protocol.hpp"

namespace fw::posix {

template <std::size_t Endpoints, std::size_t Depth = 256>
class InMemoryBus {
 public:
  // Send from `endpoint` to all the others. Returns false if `endpoint` is out of range.
  bool send(std::size_t endpoint, const pa::proto::Frame& f) {
    if (endpoint >= Endpoints) return false;
    for (std::size_t e = 0; e < Endpoints; ++e)
      if (e != endpoint && !queues_[e].push(f)) saturating_increment(overruns_[e]);
    return true;
  }
  // Next frame waiting for `endpoint`, oldest first.
  bool receive(std::size_t endpoint, pa::proto::Frame& out) {
    return endpoint < Endpoints && queues_[endpoint].pop(out);
  }
  std::uint32_t overruns(std::size_t endpoint) const {
    return endpoint < Endpoints ? overruns_[endpoint] : 0;
  }

 private:
  std::array<FixedQueue<pa::proto::Frame, Depth>, Endpoints> queues_{};
  std::array<std::uint32_t, Endpoints> overruns_{};
};

}  // namespace fw::posix
