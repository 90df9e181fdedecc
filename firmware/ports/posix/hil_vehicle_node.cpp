#include "hil_vehicle_node.hpp"

#include <ctime>

namespace fw::posix {

std::uint64_t HilVehicleNode::monotonic_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::uint64_t>(ts.tv_sec) * 1000000000ull + static_cast<std::uint64_t>(ts.tv_nsec);
}

}  // namespace fw::posix
