// fw_vehicle: one vehicle's firmware as a Linux process on its SocketCAN vehicle bus (HIL).
// The plant drives it with HIL_IMU frames; it answers with HIL_MOTORS and the flight frames.
// Everything is allocated before the loop starts; the loop allocates nothing.
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "hil_vehicle_node.hpp"
#include "socketcan.hpp"

namespace {

volatile std::sig_atomic_t g_stop = 0;
void on_signal(int) { g_stop = 1; }

int usage(const char* why) {
  std::fprintf(stderr,
               "fw_vehicle: %s\n"
               "usage: fw_vehicle --can IFACE --node N\n"
               "  --can IFACE   the vehicle's SocketCAN bus (for example vcan1)\n"
               "  --node N      this vehicle's node id, 1..14\n",
               why);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  const char* interface_name = nullptr;
  long node = -1;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--help") == 0 || std::strcmp(argv[i], "-h") == 0) {
      usage("runs one vehicle's firmware on a SocketCAN bus");
      return 0;
    }
    if (i + 1 >= argc) return usage("missing value after an option");
    if (std::strcmp(argv[i], "--can") == 0) {
      interface_name = argv[++i];
    } else if (std::strcmp(argv[i], "--node") == 0) {
      char* end = nullptr;
      node = std::strtol(argv[++i], &end, 10);
      if (end == argv[i] || *end != '\0') return usage("--node takes a whole number");
    } else {
      return usage("unknown option");
    }
  }
  if (interface_name == nullptr) return usage("--can is required");
  if (node < pa::proto::kFirstVehicleNode || node > pa::proto::kLastVehicleNode) return usage("--node must be 1..14");

  static fw::posix::SocketCan can;
  if (can.open(interface_name) != fw::posix::SocketCan::Status::ok) {
    std::fprintf(stderr, "fw_vehicle: error: %s\n", can.message());
    return 1;
  }

  fw::VehicleConfig config{};
  config.link.node = static_cast<std::uint8_t>(node);
  static fw::posix::HilVehicleNode vehicle(config);

  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  std::printf("fw_vehicle: node %ld on %s, waiting for HIL_IMU frames\n", node, interface_name);
  std::fflush(stdout);

  std::uint32_t write_failures = 0;
  pa::proto::Frame frame;
  while (g_stop == 0) {
    if (!can.read(frame, 200)) {
      if (can.status() == fw::posix::SocketCan::Status::io_error) {
        std::fprintf(stderr, "fw_vehicle: error: %s\n", can.message());
        return 1;
      }
      continue;
    }
    vehicle.on_frame(frame, [&](const pa::proto::Frame& out) {
      if (!can.write(out)) ++write_failures;
    });
  }
  std::printf("fw_vehicle: stopped (mode %u, %u frames rejected, %u writes failed)\n",
              static_cast<unsigned>(vehicle.vehicle().mode()), vehicle.vehicle().link().counters().rejected(),
              write_failures);
  return 0;
}
