// The ground CAN bus on SocketCAN (vcan0 on a laptop, can0 at the arena's radio bridge): the
// link's FrameBus for sending, and reads for the process loop, which hands each frame to
// Process::on_frame with the time it was read.
#pragma once

#include <string>

#include "groundstation/link/frame_bus.hpp"
#include "pa/socketcan.hpp"

namespace gs::service {

class SocketCanBus final : public link::FrameBus {
 public:
  // Throws std::runtime_error with the socket's own explanation (no CAN sockets in this kernel,
  // no such interface) when the interface cannot be opened.
  explicit SocketCanBus(const std::string& interface_name);

  bool send(const pa::proto::Frame& frame) override { return can_.write(frame); }
  // Waits up to timeout_ms for a frame (0: only what is queued). False on timeout, and on a
  // failed socket (failed() then says so).
  bool read(pa::proto::Frame& out, int timeout_ms) { return can_.read(out, timeout_ms); }
  bool failed() const { return can_.status() != pa::can::SocketCan::Status::ok; }
  const char* message() const { return can_.message(); }

 private:
  pa::can::SocketCan can_;
};

}  // namespace gs::service
