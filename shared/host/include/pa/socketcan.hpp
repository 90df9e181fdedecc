// A SocketCAN raw socket on a named interface (vcan0, can0, ...), for the host processes on a CAN
// bus (fw_vehicle, the ground station). Opening reports precisely why it failed: a kernel without
// CAN sockets, or an interface that does not exist.
#pragma once

#include <cstdint>

#include "pa/protocol.hpp"

namespace pa::can {

class SocketCan {
 public:
  enum class Status { ok, no_can_sockets, no_such_interface, interface_down, io_error };

  SocketCan() = default;
  SocketCan(const SocketCan&) = delete;
  SocketCan& operator=(const SocketCan&) = delete;
  ~SocketCan();

  // Open the interface; on failure `message()` says what went wrong and how to fix it.
  Status open(const char* interface_name);
  // Wait up to `timeout_ms` for a frame (-1: forever). Returns false on timeout or error
  // (status() tells which); frames that are not classic standard-ID data frames are skipped.
  bool read(pa::proto::Frame& out, int timeout_ms);
  bool write(const pa::proto::Frame& frame);

  Status status() const { return status_; }
  // The socket, for a caller that waits on several buses at once (poll); -1 when not open.
  int fd() const { return fd_; }
  const char* message() const { return message_; }

 private:
  void fail(Status s, const char* fmt, const char* a, const char* b);

  int fd_ = -1;
  Status status_ = Status::io_error;
  char message_[256] = "not opened";
};

}  // namespace pa::can
