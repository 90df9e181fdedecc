// A stand-in for QEMU running the PIL image (firmware/ports/mps2_an386/pil_main.cpp), for
// emulated_firmware_test: started with QEMU's command line, it checks the flags the contract
// names (hil/sil/emulated_firmware.hpp), reads pil_vehicle.cfg from its working directory,
// connects to the socket of `-chardev socket,id=pil,path=...` and answers the serial frames as
// the image does, with the firmware core compiled for this host: per tick, the core's frames,
// HIL_TICK_COST (here 100000 + the tick, so a test can tell which tick it belongs to), then
// HIL_MOTORS. What it does is chosen by the environment variable PA_PIL_STAND_IN:
//   (unset) or "answer"  serve until the line closes
//   "exit"               say so on stderr and exit with status 3 before connecting
//   "no_connect"         say so on stderr and never connect
//   "hang_after=N"       answer N ticks, then read nothing more
//   "exit_after=N"       answer N ticks, then exit with status 4
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "fw/config.hpp"
#include "hil_vehicle_node.hpp"
#include "pa/protocol.hpp"
#include "pa/serial_frame.hpp"

namespace {

int fail(const std::string& why) {
  std::fprintf(stderr, "stand-in: %s\n", why.c_str());
  return 2;
}

void write_frame(int fd, const pa::proto::Frame& f) {
  std::array<std::uint8_t, pa::serial_frame::kMaxBytes> bytes;
  const std::size_t n = pa::serial_frame::encode(f, bytes);
  std::size_t done = 0;
  while (done < n) {
    const ssize_t w = write(fd, bytes.data() + done, n - done);
    if (w <= 0) std::exit(6);
    done += static_cast<std::size_t>(w);
  }
}

bool is_motors(const pa::proto::Frame& f) {
  return pa::proto::id_type(f.id) == static_cast<std::uint8_t>(pa::proto::Type::hil_motors);
}

}  // namespace

int main(int argc, char** argv) {
  std::string socket_path, icount, semihosting, kernel, serial;
  for (int i = 1; i + 1 < argc; ++i) {
    const std::string flag = argv[i], value = argv[i + 1];
    if (flag == "-chardev" && value.rfind("socket,id=pil,path=", 0) == 0) socket_path = value.substr(19);
    if (flag == "-icount") icount = value;
    if (flag == "-semihosting-config") semihosting = value;
    if (flag == "-kernel") kernel = value;
    if (flag == "-serial") serial = value;
  }
  if (socket_path.empty() || icount.rfind("shift=", 0) != 0 || semihosting != "enable=on,target=native" ||
      kernel.empty() || serial != "chardev:pil")
    return fail("not QEMU's command line of the contract");

  const char* mode_env = std::getenv("PA_PIL_STAND_IN");
  const std::string mode = mode_env != nullptr ? mode_env : "answer";
  long stop_after = -1;
  bool hang = false;
  if (mode == "exit") {
    std::fprintf(stderr, "stand-in: exiting at once as asked\n");
    return 3;
  }
  if (mode == "no_connect") {
    std::fprintf(stderr, "stand-in: not connecting as asked\n");
    std::fflush(stderr);
    for (;;) pause();
  }
  if (mode.rfind("hang_after=", 0) == 0) {
    stop_after = std::atol(mode.c_str() + 11);
    hang = true;
  } else if (mode.rfind("exit_after=", 0) == 0) {
    stop_after = std::atol(mode.c_str() + 11);
  }

  std::ifstream file("pil_vehicle.cfg", std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  if (bytes.size() != 8 + sizeof(fw::VehicleConfig) || bytes.compare(0, 4, "PAVC") != 0)
    return fail("pil_vehicle.cfg is not PAVC + size + fw::VehicleConfig");
  std::uint32_t size = 0;
  for (int i = 0; i < 4; ++i)
    size |= static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[4 + i])) << (8 * i);
  if (size != sizeof(fw::VehicleConfig)) return fail("pil_vehicle.cfg's size field is wrong");
  fw::VehicleConfig config;
  std::memcpy(&config, bytes.data() + 8, sizeof config);
  const std::uint8_t node = config.link.vehicle.node();
  fw::posix::HilVehicleNode vehicle(config);

  const int fd = socket(AF_UNIX, SOCK_STREAM, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  std::strncpy(address.sun_path, socket_path.c_str(), sizeof address.sun_path - 1);
  if (fd < 0 || connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0)
    return fail("cannot connect to " + socket_path);

  pa::serial_frame::Decoder decoder;
  std::vector<pa::proto::Frame> sent;
  long ticks = 0;
  std::array<std::uint8_t, 256> buffer;
  for (;;) {
    const ssize_t n = read(fd, buffer.data(), buffer.size());
    if (n <= 0) return 0;
    for (ssize_t i = 0; i < n; ++i) {
      pa::proto::Frame frame;
      if (!decoder.push(buffer[static_cast<std::size_t>(i)], frame)) continue;
      sent.clear();
      vehicle.on_frame(frame, [&](const pa::proto::Frame& f) { sent.push_back(f); });
      if (sent.empty()) continue;
      if (ticks == stop_after) {
        if (!hang) {
          std::fprintf(stderr, "stand-in: exiting after %ld ticks as asked\n", ticks);
          return 4;
        }
        std::fprintf(stderr, "stand-in: hanging after %ld ticks as asked\n", ticks);
        std::fflush(stderr);
        for (;;) pause();
      }
      const pa::proto::Frame* motors = nullptr;
      for (const pa::proto::Frame& f : sent) {
        if (motors == nullptr && is_motors(f)) motors = &f;
        else write_frame(fd, f);
      }
      const auto tick = static_cast<std::uint16_t>(motors->data[6] | (motors->data[7] << 8));
      pa::proto::Frame cost;
      pa::proto::encode(pa::proto::HilTickCost{tick, 100000u + tick}, node, cost);
      write_frame(fd, cost);
      write_frame(fd, *motors);
      ++ticks;
    }
  }
}
