// The ground CAN bus on SocketCAN (vcan0 on a laptop, can0 at the arena's radio bridge), as a
// GroundBus (ground_bus.hpp).
#pragma once

#include <string>

#include "groundstation/service/ground_bus.hpp"
#include "pa/socketcan.hpp"

namespace gs::service {

class SocketCanBus final : public GroundBus {
 public:
  // Throws std::runtime_error with the socket's own explanation (no CAN sockets in this kernel,
  // no such interface) when the interface cannot be opened.
  explicit SocketCanBus(const std::string& interface_name);

  bool send(const pa::proto::Frame& frame) override { return can_.write(frame); }
  bool read(pa::proto::Frame& out, int timeout_ms) override { return can_.read(out, timeout_ms); }
  bool failed() const override { return can_.status() != pa::can::SocketCan::Status::ok; }
  const char* message() const override { return can_.message(); }

 private:
  pa::can::SocketCan can_;
};

}  // namespace gs::service
