#include "groundstation/link/frame_bus.hpp"

namespace gs::link {

bool InMemoryFrameBus::send(const pa::proto::Frame& frame) {
  if (frames_.size() >= capacity_) return false;
  frames_.push_back(frame);
  return true;
}

std::vector<pa::proto::Frame> InMemoryFrameBus::take() {
  std::vector<pa::proto::Frame> out;
  out.swap(frames_);
  return out;
}

}  // namespace gs::link
