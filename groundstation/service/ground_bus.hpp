// The ground station's bus to its vehicles as the process loop uses it: the link's FrameBus for
// sending, and reads, each frame handed to Process::on_frame with the time it was read. Two
// kinds: the ground CAN bus (socketcan_bus.hpp: vcan0 on a laptop, can0 at a radio bridge) and
// each vehicle's serial radio (radio_bus.hpp).
#pragma once

#include <string>

#include "groundstation/link/frame_bus.hpp"

namespace gs::service {

class GroundBus : public link::FrameBus {
 public:
  // Waits up to timeout_ms for a frame (0: only what has arrived). False when none came, possibly
  // before the timeout (the caller loops), and when the bus has failed for good (failed() says so).
  virtual bool read(pa::proto::Frame& out, int timeout_ms) = 0;
  virtual bool failed() const = 0;
  virtual const char* message() const = 0;
  // What the bus counted, for the run's summary (empty: nothing of its own).
  virtual std::string summary() const { return {}; }
};

}  // namespace gs::service
