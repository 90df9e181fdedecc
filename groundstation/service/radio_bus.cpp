#include "groundstation/service/radio_bus.hpp"

#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace gs::service {
namespace {

using Clock = std::chrono::steady_clock;
constexpr auto kRetryPeriod = std::chrono::seconds(1);

speed_t speed_of(unsigned baud) {
  switch (baud) {
    case 9600: return B9600;
    case 19200: return B19200;
    case 38400: return B38400;
    case 57600: return B57600;
    case 115200: return B115200;
    case 230400: return B230400;
    case 460800: return B460800;
    case 921600: return B921600;
    default: return B0;
  }
}

std::string system_error(const std::string& path, const char* what, int error) {
  return "radio " + path + ": " + what + ": " + std::strerror(error);
}

}  // namespace

bool RadioBus::supported_baud(unsigned baud) { return speed_of(baud) != B0; }

RadioBus::RadioBus(std::vector<RadioPort> ports, unsigned baud) : baud_(baud) {
  if (!supported_baud(baud))
    throw std::runtime_error("radio: " + std::to_string(baud) + " baud is not a rate a port can be set to");
  for (std::size_t i = 0; i < ports.size(); ++i)
    for (std::size_t j = i + 1; j < ports.size(); ++j)
      if (ports[i].vehicle == ports[j].vehicle)
        throw std::runtime_error("radio: two ports for vehicle " + std::to_string(ports[i].vehicle.node()));
  radios_.reserve(ports.size());
  poll_fds_.reserve(ports.size());
  polled_.reserve(ports.size());
  try {
    for (RadioPort& port : ports) {
      radios_.push_back(Radio{std::move(port), -1, {}, {}, {}, {}});
      open_port(radios_.back());
    }
  } catch (...) {
    for (Radio& r : radios_)
      if (r.fd >= 0) close_port(r.fd);
    throw;
  }
}

RadioBus::~RadioBus() {
  for (Radio& r : radios_)
    if (r.fd >= 0) close_port(r.fd);
}

// A tty's close waits up to its closing_wait (30 s) for output to drain: a failed modem's would.
void RadioBus::close_port(int fd) {
  ::tcflush(fd, TCOFLUSH);
  ::close(fd);
}

void RadioBus::open_port(Radio& radio) {
  const int fd = ::open(radio.port.path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw std::runtime_error(system_error(radio.port.path, "cannot open", errno));
  termios tio{};
  if (::tcgetattr(fd, &tio) != 0) {
    const int error = errno;
    ::close(fd);
    throw std::runtime_error(system_error(radio.port.path, "not a serial port", error));
  }
  // Raw bytes, 8N1, no flow control, no modem lines: the frames carry their own sync and CRC.
  ::cfmakeraw(&tio);
  tio.c_cflag = (tio.c_cflag & ~static_cast<tcflag_t>(CSTOPB | PARENB | CRTSCTS)) | CLOCAL | CREAD;
  ::cfsetispeed(&tio, speed_of(baud_));
  ::cfsetospeed(&tio, speed_of(baud_));
  if (::tcsetattr(fd, TCSANOW, &tio) != 0) {
    const int error = errno;
    ::close(fd);
    throw std::runtime_error(system_error(radio.port.path, "cannot set the line up", error));
  }
  radio.fd = fd;
  radio.decoder = {};
  radio.counted = {};
  radio.output.clear();
}

void RadioBus::fail(Radio& radio, const char* what, int error) {
  close_port(radio.fd);
  radio.fd = -1;
  counters_.lost_bytes += radio.output.size();
  radio.output.clear();
  radio.retry_at = Clock::now() + kRetryPeriod;
  ++counters_.port_failures;
  message_ =
      error != 0 ? system_error(radio.port.path, what, error) : "radio " + radio.port.path + ": " + what;
}

void RadioBus::retry_closed() {
  for (Radio& r : radios_) {
    if (r.fd >= 0 || Clock::now() < r.retry_at) continue;
    try {
      open_port(r);
      ++counters_.reopened;
    } catch (const std::runtime_error& e) {
      message_ = e.what();
      r.retry_at = Clock::now() + kRetryPeriod;
    }
  }
}

bool RadioBus::send(const pa::proto::Frame& frame) {
  const std::uint8_t node = pa::proto::id_node(frame.id);
  std::array<std::uint8_t, pa::serial_frame::kMaxBytes> bytes{};
  const std::size_t n = pa::serial_frame::encode(frame, bytes);
  bool sent = false;
  for (Radio& r : radios_) {
    if (node != pa::proto::kBroadcastNode && node != r.port.vehicle.node()) continue;
    if (n == 0 || r.fd < 0 || r.output.size() + kFrameRoom > kOutputCapacity) {
      ++counters_.unsent;
      continue;
    }
    r.output.insert(r.output.end(), bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(n));
    ++counters_.frames_out;
    flush(r);
    sent = true;
  }
  return sent;
}

void RadioBus::flush(Radio& radio) {
  while (radio.fd >= 0 && !radio.output.empty()) {
    const ssize_t n = ::write(radio.fd, radio.output.data(), radio.output.size());
    if (n > 0) {
      counters_.bytes_out += static_cast<std::uint64_t>(n);
      radio.output.erase(radio.output.begin(), radio.output.begin() + n);
    } else if (n < 0 && errno == EINTR) {
      continue;
    } else if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
      return;  // the line is busy: the rest goes at the next send or read
    } else {
      fail(radio, "write failed", n < 0 ? errno : 0);
    }
  }
}

void RadioBus::drain(Radio& radio) {
  std::array<std::uint8_t, 512> buffer{};
  for (;;) {
    const ssize_t n = ::read(radio.fd, buffer.data(), buffer.size());
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) break;
    if (n <= 0) {  // 0: the line hung up; an error (EIO: the modem's end is gone)
      fail(radio, n == 0 ? "the line hung up" : "read failed", n < 0 ? errno : 0);
      break;
    }
    counters_.bytes_in += static_cast<std::uint64_t>(n);
    for (ssize_t i = 0; i < n; ++i) {
      pa::proto::Frame frame;
      if (!radio.decoder.push(buffer[static_cast<std::size_t>(i)], frame)) continue;
      if (pa::proto::id_node(frame.id) != radio.port.vehicle.node()) {
        ++counters_.foreign;
      } else if (frames_.size() >= kInputCapacity) {
        ++counters_.unread;
      } else {
        ++counters_.frames_in;
        frames_.push_back(frame);
      }
    }
  }
  const pa::serial_frame::DecoderStats& s = radio.decoder.stats();
  counters_.crc_errors += s.crc_errors - radio.counted.crc_errors;
  counters_.bad_headers += s.bad_headers - radio.counted.bad_headers;
  radio.counted = s;
}

bool RadioBus::read(pa::proto::Frame& out, int timeout_ms) {
  retry_closed();
  if (frames_.empty()) {
    // Kept between calls (reserved for every radio at construction): the loop allocates nothing.
    std::vector<pollfd>& fds = poll_fds_;
    std::vector<Radio*>& polled = polled_;
    fds.clear();
    polled.clear();
    for (Radio& r : radios_) {
      if (r.fd < 0) continue;
      flush(r);
      if (r.fd < 0) continue;
      const short events = static_cast<short>(POLLIN | (r.output.empty() ? 0 : POLLOUT));
      fds.push_back({r.fd, events, 0});
      polled.push_back(&r);
    }
    // With every port closed, wait all the same: the loop keeps its pace while they are retried.
    const int ready = ::poll(fds.data(), fds.size(), std::max(0, timeout_ms));
    for (std::size_t i = 0; ready > 0 && i < fds.size(); ++i) {
      Radio& r = *polled[i];
      if ((fds[i].revents & (POLLIN | POLLHUP | POLLERR)) != 0) drain(r);
      if (r.fd >= 0 && (fds[i].revents & POLLNVAL) != 0) fail(r, "the port closed", 0);
      if (r.fd >= 0 && (fds[i].revents & POLLOUT) != 0) flush(r);
    }
  }
  if (frames_.empty()) return false;
  out = frames_.front();
  frames_.pop_front();
  return true;
}

bool RadioBus::connected(pa::VehicleId vehicle) const {
  return std::any_of(radios_.begin(), radios_.end(),
                     [&](const Radio& r) { return r.port.vehicle == vehicle && r.fd >= 0; });
}

std::string RadioBus::summary() const {
  const auto u = [](std::uint64_t v) { return std::to_string(v); };
  const RadioCounters& c = counters_;
  return "radios: frames in " + u(c.frames_in) + ", out " + u(c.frames_out) + "; bytes in " + u(c.bytes_in) +
         ", out " + u(c.bytes_out) + "; dropped: " + u(c.crc_errors) + " bad CRC, " + u(c.bad_headers) +
         " bad headers, " + u(c.foreign) + " from another node, " + u(c.unsent) + " unsent, " + u(c.unread) +
         " unread; port failures " + u(c.port_failures) + " (" + u(c.lost_bytes) +
         " bytes lost with them), reopened " + u(c.reopened) + "\n";
}

}  // namespace gs::service
