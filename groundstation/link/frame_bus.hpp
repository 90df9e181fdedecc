// The ground station's bus to its vehicles as the link sees it: somewhere to queue frames for
// transmission. InMemoryFrameBus for simulation and tests (the caller collects what was sent and
// carries it to the vehicles); in the process, the ground CAN bus or each vehicle's serial radio
// (groundstation/service/ground_bus.hpp).
//
// Receiving is not part of the interface: whoever reads the bus hands each frame to
// GroundLink::on_frame with the ground time it was read, so the link needs no thread or clock.
#pragma once

#include <cstddef>
#include <vector>

#include "pa/protocol.hpp"

namespace gs::link {

class FrameBus {
 public:
  virtual ~FrameBus() = default;
  // Queue one frame for transmission; false when the bus refused it (the link counts it).
  virtual bool send(const pa::proto::Frame& frame) = 0;
};

// Keeps what was sent until take(). Bounded like a real transmit queue: beyond `capacity`
// untaken frames send() refuses, so a caller that never takes cannot grow it without limit.
class InMemoryFrameBus final : public FrameBus {
 public:
  static constexpr std::size_t kDefaultCapacity = 4096;
  explicit InMemoryFrameBus(std::size_t capacity = kDefaultCapacity) : capacity_(capacity) {}

  bool send(const pa::proto::Frame& frame) override;
  // Everything sent since the last take, oldest first.
  std::vector<pa::proto::Frame> take();
  std::size_t pending() const { return frames_.size(); }

 private:
  std::size_t capacity_;
  std::vector<pa::proto::Frame> frames_;
};

}  // namespace gs::link
