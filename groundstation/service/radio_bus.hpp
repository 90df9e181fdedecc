// Each vehicle of the act on its own serial radio (a transparent modem on the flight
// controller's UART and one on the ground station's serial port, `groundstation run --radio
// N=PATH`), as a GroundBus (ground_bus.hpp). The frames are the flight image's
// (pa/serial_frame.hpp). A frame goes out on the radio of the node it addresses, a broadcast on
// every radio; frames are read back one at a time, the oldest first.
//
// Bad input costs the frames it touches and is counted: line noise and cut frames (the
// decoder's CRC and header checks), and a frame on a radio from a node other than its vehicle.
// A port that fails (a modem unplugged: a read or write error, or the line hung up) is closed and
// tried again every second; meanwhile its vehicle is silent, which the ground link sees as a lost
// vehicle and the mission as its failsafe. Never fatal: failed() stays false.
#pragma once

#include <poll.h>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <string>
#include <vector>

#include "groundstation/service/ground_bus.hpp"
#include "pa/serial_frame.hpp"
#include "pa/vehicle_id.hpp"

namespace gs::service {

struct RadioPort {
  pa::VehicleId vehicle{pa::proto::kGroundNode};
  std::string path;  // the modem's serial port, /dev/ttyUSB0
};

struct RadioCounters {
  std::uint64_t frames_in = 0;
  std::uint64_t frames_out = 0;
  std::uint64_t bytes_in = 0;
  std::uint64_t bytes_out = 0;
  std::uint64_t crc_errors = 0;   // noise, or a frame cut short
  std::uint64_t bad_headers = 0;  // a reserved bit set or a length above 8
  std::uint64_t foreign = 0;      // from a node other than the radio's vehicle
  std::uint64_t unsent = 0;       // frames not queued: no port open, the queue full, or invalid
  std::uint64_t unread = 0;       // frames dropped: more than kInputCapacity waiting to be read
  std::uint64_t lost_bytes = 0;   // queued for a port that then failed
  std::uint64_t port_failures = 0;
  std::uint64_t reopened = 0;
};

class RadioBus final : public GroundBus {
 public:
  // The baud rates a port may be set to (termios' standard ones, 9600 to 921600).
  static bool supported_baud(unsigned baud);
  // Opens every port at `baud` (raw, 8N1, no flow control). Throws std::runtime_error naming the
  // port and the system's reason when one cannot be opened or set up, or when two ports are one
  // vehicle's.
  RadioBus(std::vector<RadioPort> ports, unsigned baud);
  ~RadioBus() override;
  RadioBus(const RadioBus&) = delete;
  RadioBus& operator=(const RadioBus&) = delete;

  bool send(const pa::proto::Frame& frame) override;
  bool read(pa::proto::Frame& out, int timeout_ms) override;
  bool failed() const override { return false; }
  const char* message() const override { return message_.c_str(); }  // the last port failure
  std::string summary() const override;

  const RadioCounters& counters() const { return counters_; }
  // Whether `vehicle`'s port is open now.
  bool connected(pa::VehicleId vehicle) const;

 private:
  static constexpr std::size_t kOutputCapacity = 4096;  // bytes queued per port: 0.36 s at 115200
  static constexpr std::size_t kInputCapacity = 1024;   // frames read and not yet taken
  // A frame is queued only with room for one more after it: the AUTH the link sends right after a
  // ground frame, without which the vehicle drops the frame.
  static constexpr std::size_t kFrameRoom = 2 * pa::serial_frame::kMaxBytes;
  struct Radio {
    RadioPort port;
    int fd = -1;
    pa::serial_frame::Decoder decoder;
    pa::serial_frame::DecoderStats counted{};  // the decoder's counts already added
    std::vector<std::uint8_t> output;
    std::chrono::steady_clock::time_point retry_at{};
  };

  void open_port(Radio& radio);  // throws std::runtime_error
  void fail(Radio& radio, const char* what, int error);
  static void close_port(int fd);  // without waiting for unsent output
  void retry_closed();
  void flush(Radio& radio);
  void drain(Radio& radio);  // reads what the port has into frames_

  unsigned baud_;
  std::vector<Radio> radios_;
  std::vector<pollfd> poll_fds_;  // read()'s, by radio polled
  std::vector<Radio*> polled_;
  std::deque<pa::proto::Frame> frames_;
  RadioCounters counters_;
  std::string message_;
};

}  // namespace gs::service
