// Each vehicle's serial radio (groundstation/service/radio_bus.hpp) on a pseudo-terminal: the
// test holds the modem's end (the pty's master), the bus opens the port (its slave) as it would a
// USB modem. Frames both ways in the flight image's framing, routed by node; noise, cut frames and
// another node's frames dropped and counted; an unplugged modem a silent vehicle, never a crash.
#include "groundstation/service/radio_bus.hpp"

#include <fcntl.h>
#include <pty.h>
#include <unistd.h>
#include <catch2/catch.hpp>

#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using gs::service::RadioBus;
using gs::service::RadioPort;
using pa::proto::Frame;

// A modem's end of a serial line: the pty's master, non-blocking.
struct Modem {
  int master = -1;
  std::string port;  // the slave's path, for the bus
  Modem() {
    int slave = -1;
    char name[128] = {};
    REQUIRE(::openpty(&master, &slave, name, nullptr, nullptr) == 0);
    // The slave stays open only in the bus: closing the master then hangs the line up.
    ::close(slave);
    ::fcntl(master, F_SETFL, O_NONBLOCK);
    port = name;
  }
  ~Modem() { unplug(); }
  void unplug() {
    if (master >= 0) ::close(master);
    master = -1;
  }
  void write_bytes(const std::vector<std::uint8_t>& bytes) const {
    REQUIRE(::write(master, bytes.data(), bytes.size()) == static_cast<ssize_t>(bytes.size()));
  }
  void write_frame(const Frame& f) const {
    std::array<std::uint8_t, pa::serial_frame::kMaxBytes> bytes{};
    const std::size_t n = pa::serial_frame::encode(f, bytes);
    write_bytes({bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(n)});
  }
  // Every frame the bus wrote to this modem so far.
  std::vector<Frame> frames() {
    std::vector<Frame> out;
    std::uint8_t buffer[256];
    ssize_t n = 0;
    while ((n = ::read(master, buffer, sizeof buffer)) > 0)
      for (ssize_t i = 0; i < n; ++i) {
        Frame f;
        if (decoder.push(buffer[i], f)) out.push_back(f);
      }
    return out;
  }
  pa::serial_frame::Decoder decoder;
};

Frame heartbeat_from(std::uint8_t node, std::uint32_t uptime_ms) {
  pa::proto::VehicleHeartbeat h{};
  h.uptime_ms = uptime_ms;
  Frame f;
  REQUIRE(pa::proto::encode(h, node, f));
  return f;
}

Frame kill_to(std::uint8_t node) {
  Frame f;
  REQUIRE(pa::proto::encode(pa::proto::Kill{0x1234, pa::proto::KillReason::operator_request}, node, f));
  return f;
}

// Reads until `count` frames came or half a second passed.
std::vector<Frame> read_frames(RadioBus& bus, std::size_t count) {
  std::vector<Frame> out;
  Frame f;
  for (int i = 0; i < 50 && out.size() < count; ++i)
    if (bus.read(f, 10)) out.push_back(f);
  return out;
}

}  // namespace

TEST_CASE("Frames go out on the radio of the node they address and come back in order") {
  Modem one, two;
  RadioBus bus({{pa::kVehicle1, one.port}, {pa::kVehicle2, two.port}}, 115200);
  CHECK(bus.connected(pa::kVehicle1));
  CHECK(bus.connected(pa::kVehicle2));

  CHECK(bus.send(kill_to(1)));
  CHECK(bus.send(kill_to(pa::proto::kBroadcastNode)));  // both radios
  CHECK_FALSE(bus.send(kill_to(3)));                    // no radio for node 3
  const std::vector<Frame> at_one = one.frames();
  const std::vector<Frame> at_two = two.frames();
  REQUIRE(at_one.size() == 2);
  REQUIRE(at_two.size() == 1);
  CHECK(at_one[0].id == kill_to(1).id);
  CHECK(at_one[0].data == kill_to(1).data);
  CHECK(at_two[0].id == kill_to(pa::proto::kBroadcastNode).id);

  one.write_frame(heartbeat_from(1, 10));
  one.write_frame(heartbeat_from(1, 30));
  two.write_frame(heartbeat_from(2, 20));
  const std::vector<Frame> in = read_frames(bus, 3);
  REQUIRE(in.size() == 3);
  // Each radio's frames in the order they came.
  std::vector<std::uint32_t> from_one;
  for (const Frame& f : in) {
    pa::proto::Message m;
    REQUIRE(pa::proto::decode(f, m) == pa::proto::DecodeStatus::ok);
    if (pa::proto::id_node(f.id) == 1) from_one.push_back(m.vehicle_heartbeat.uptime_ms);
  }
  CHECK(from_one == std::vector<std::uint32_t>{10, 30});
  CHECK(bus.counters().frames_in == 3);
  CHECK(bus.counters().frames_out == 3);
  CHECK(bus.summary().find("frames in 3, out 3") != std::string::npos);
}

TEST_CASE(
    "Noise, cut frames and another vehicle's frames are dropped and counted; the frames around them come") {
  Modem one;
  RadioBus bus({{pa::kVehicle1, one.port}}, 115200);
  one.write_frame(heartbeat_from(1, 1));
  one.write_bytes({0x7E, 0x12, 0x34, 0x55});                    // a frame cut short (then a sync byte)
  one.write_bytes({0x00, 0xFF, 0x7E, 0x03, 0x98, 0x01, 0x02});  // noise: a length of 9
  std::array<std::uint8_t, pa::serial_frame::kMaxBytes> bytes{};
  const std::size_t n = pa::serial_frame::encode(heartbeat_from(1, 2), bytes);
  bytes[4] ^= 0x10;  // a bit flipped in the payload
  one.write_bytes({bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(n)});
  one.write_frame(heartbeat_from(2, 3));  // vehicle 2's on vehicle 1's radio
  one.write_frame(heartbeat_from(1, 4));
  const std::vector<Frame> in = read_frames(bus, 2);
  REQUIRE(in.size() == 2);
  pa::proto::Message m;
  REQUIRE(pa::proto::decode(in[0], m) == pa::proto::DecodeStatus::ok);
  CHECK(m.vehicle_heartbeat.uptime_ms == 1);
  REQUIRE(pa::proto::decode(in[1], m) == pa::proto::DecodeStatus::ok);
  CHECK(m.vehicle_heartbeat.uptime_ms == 4);
  CHECK(bus.counters().crc_errors + bus.counters().bad_headers >= 2);
  CHECK(bus.counters().foreign == 1);

  // A flood of random bytes: whatever decodes by chance is vehicle 1's or counted as foreign.
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> byte(0, 255);
  for (int block = 0; block < 20; ++block) {
    std::vector<std::uint8_t> noise(1000);
    for (std::uint8_t& b : noise) b = static_cast<std::uint8_t>(byte(rng));
    one.write_bytes(noise);
    Frame f;
    while (bus.read(f, 0)) CHECK(pa::proto::id_node(f.id) == 1);
  }
  // Whatever the terminal still holds, within a second.
  Frame f;
  for (int i = 0; i < 100 && bus.counters().bytes_in < 20000; ++i)
    if (bus.read(f, 10)) CHECK(pa::proto::id_node(f.id) == 1);
  CHECK(bus.counters().bytes_in >= 20000);
}

TEST_CASE("An unplugged modem is a silent vehicle: counted, retried, never fatal") {
  Modem one, two;
  RadioBus bus({{pa::kVehicle1, one.port}, {pa::kVehicle2, two.port}}, 115200);
  one.unplug();
  Frame f;
  for (int i = 0; i < 5; ++i) CHECK_FALSE(bus.read(f, 5));
  CHECK_FALSE(bus.failed());
  CHECK_FALSE(bus.connected(pa::kVehicle1));
  CHECK(bus.connected(pa::kVehicle2));
  CHECK(bus.counters().port_failures == 1);
  CHECK(std::string(bus.message()).find(one.port) != std::string::npos);
  CHECK_FALSE(bus.send(kill_to(1)));  // nowhere to go
  CHECK(bus.counters().unsent == 1);
  // The other radio goes on.
  two.write_frame(heartbeat_from(2, 5));
  CHECK(read_frames(bus, 1).size() == 1);
}

TEST_CASE(
    "A port that is not a serial line, two ports for one vehicle, or an odd rate are refused at start") {
  Modem one;
  CHECK_THROWS_WITH(RadioBus({{pa::kVehicle1, "/dev/null"}}, 115200), Catch::Contains("not a serial port"));
  CHECK_THROWS_WITH(RadioBus({{pa::kVehicle1, "/nonexistent/tty"}}, 115200), Catch::Contains("cannot open"));
  CHECK_THROWS_WITH(RadioBus({{pa::kVehicle1, one.port}, {pa::kVehicle1, one.port}}, 115200),
                    Catch::Contains("two ports for vehicle 1"));
  CHECK_THROWS_WITH(RadioBus({{pa::kVehicle1, one.port}}, 100000), Catch::Contains("100000 baud"));
  CHECK(RadioBus::supported_baud(115200));
  CHECK_FALSE(RadioBus::supported_baud(0));
}
