#include "pa/socketcan.hpp"

#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace pa::can {

SocketCan::~SocketCan() {
  if (fd_ >= 0) ::close(fd_);
}

void SocketCan::fail(Status s, const char* fmt, const char* a, const char* b) {
  status_ = s;
  std::snprintf(message_, sizeof message_, fmt, a, b);
}

SocketCan::Status SocketCan::open(const char* interface_name) {
  if (interface_name == nullptr || interface_name[0] == '\0' || std::strlen(interface_name) >= IFNAMSIZ) {
    fail(Status::no_such_interface, "invalid CAN interface name '%s'%s", interface_name ? interface_name : "",
         "");
    return status_;
  }
  fd_ = ::socket(PF_CAN, SOCK_RAW, CAN_RAW);
  if (fd_ < 0) {
    fail(Status::no_can_sockets,
         "this kernel has no CAN sockets (socket(AF_CAN): %s); load them with 'modprobe can-raw vcan' on a "
         "normal Linux kernel, or run the HIL tests in the QEMU guest%s",
         std::strerror(errno), "");
    return status_;
  }
  ifreq ifr{};
  std::strncpy(ifr.ifr_name, interface_name, IFNAMSIZ - 1);
  if (::ioctl(fd_, SIOCGIFINDEX, &ifr) < 0) {
    fail(
        Status::no_such_interface,
        "CAN interface '%s' does not exist (create it with 'ip link add dev %s type vcan && ip link set up dev "
        "<name>')",
        interface_name, interface_name);
    return status_;
  }
  sockaddr_can addr{};
  addr.can_family = AF_CAN;
  addr.can_ifindex = ifr.ifr_ifindex;
  if (::bind(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) < 0) {
    fail(Status::interface_down, "cannot bind to CAN interface '%s': %s", interface_name,
         std::strerror(errno));
    return status_;
  }
  status_ = Status::ok;
  std::snprintf(message_, sizeof message_, "open on %s", interface_name);
  return status_;
}

bool SocketCan::read(pa::proto::Frame& out, int timeout_ms) {
  if (fd_ < 0) return false;
  for (;;) {
    pollfd p{fd_, POLLIN, 0};
    const int ready = ::poll(&p, 1, timeout_ms);
    if (ready == 0) return false;
    if (ready < 0) {
      if (errno == EINTR) continue;
      fail(Status::io_error, "poll on CAN socket failed: %s%s", std::strerror(errno), "");
      return false;
    }
    can_frame raw{};
    const ssize_t n = ::read(fd_, &raw, sizeof raw);
    if (n != static_cast<ssize_t>(sizeof raw)) {
      if (n < 0 && errno == EINTR) continue;
      fail(Status::io_error, "read from CAN socket failed: %s%s", n < 0 ? std::strerror(errno) : "short read",
           "");
      return false;
    }
    // Only classic data frames with standard identifiers belong to the protocol.
    if ((raw.can_id & (CAN_EFF_FLAG | CAN_RTR_FLAG | CAN_ERR_FLAG)) != 0 || raw.can_dlc > 8) continue;
    out.id = static_cast<std::uint16_t>(raw.can_id & CAN_SFF_MASK);
    out.len = raw.can_dlc;
    std::memcpy(out.data.data(), raw.data, 8);
    return true;
  }
}

bool SocketCan::write(const pa::proto::Frame& frame) {
  if (fd_ < 0 || frame.len > 8) return false;
  can_frame raw{};
  raw.can_id = frame.id & CAN_SFF_MASK;
  raw.can_dlc = frame.len;
  std::memcpy(raw.data, frame.data.data(), 8);
  return ::write(fd_, &raw, sizeof raw) == static_cast<ssize_t>(sizeof raw);
}

}  // namespace pa::can
