// fw_vehicle: one vehicle's firmware as a Linux process on its SocketCAN vehicle bus (HIL).
// The plant drives it with HIL_IMU frames; it answers with HIL_MOTORS and the flight frames.
// Everything is allocated before the loop starts; the loop allocates nothing.
#include <sys/random.h>

#include <csignal>
#include <cstdio>
#include <iostream>
#include <iterator>
#include <optional>
#include <string>

#include "hil_vehicle_node.hpp"
#include "pa/command_line.hpp"
#include "pa/link_key_file.hpp"
#include "pa/socketcan.hpp"

namespace {

volatile std::sig_atomic_t g_stop = 0;
void on_signal(int) { g_stop = 1; }

}  // namespace

int main(int argc, char** argv) {
  // The command line is read once at process start, before anything runs on the bus: the one
  // place where this port allocates (CLI11), and the firmware core knows nothing of it.
  std::string interface_name;
  std::string key_path;
  unsigned node = 0;
  {
    CLI::App app("", "fw_vehicle");
    pa::cli::describe(
        app, "usage: fw_vehicle --can IFACE --node N --key FILE",
        "Runs one vehicle's firmware on a SocketCAN bus (HIL): the plant drives it with HIL_IMU\n"
        "frames; it answers with HIL_MOTORS and the flight frames. It acts only on ground frames\n"
        "authenticated with its link key (docs/security.md).");
    app.add_option("--can", interface_name, "the vehicle's SocketCAN bus (for example vcan1)")
        ->type_name("IFACE")
        ->required()
        ->check(pa::cli::non_empty("needs an interface name"));
    app.add_option("--node", node, "this vehicle's node id, 1..14")
        ->type_name("N")
        ->required()
        ->check(pa::cli::count(pa::proto::kFirstVehicleNode, pa::proto::kLastVehicleNode, "must be 1..14"));
    app.add_option("--key", key_path, "this vehicle's link key: a file of 32 hex digits")
        ->type_name("FILE")
        ->required()
        ->check(pa::cli::non_empty("needs a file name"));
    if (const std::optional<int> code = pa::cli::parse(app, argc, argv, std::cout, std::cerr)) return *code;
  }

  fw::VehicleConfig config{};
  config.link.vehicle = pa::VehicleId(static_cast<std::uint8_t>(node));
  std::string error;
  if (!pa::auth::read_key_file(key_path, config.link.key, error)) {
    std::fprintf(stderr, "fw_vehicle: error: %s\n", error.c_str());
    return 2;
  }
  // Every boot its own session: a nonce from the kernel's entropy.
  if (getrandom(&config.link.session_nonce, sizeof config.link.session_nonce, 0) !=
      static_cast<ssize_t>(sizeof config.link.session_nonce)) {
    std::fprintf(stderr, "fw_vehicle: error: no entropy for the link session (getrandom failed)\n");
    return 1;
  }

  static pa::can::SocketCan can;
  if (can.open(interface_name.c_str()) != pa::can::SocketCan::Status::ok) {
    std::fprintf(stderr, "fw_vehicle: error: %s\n", can.message());
    return 1;
  }

  static fw::posix::HilVehicleNode vehicle(config);

  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  std::printf("fw_vehicle: node %u on %s, waiting for HIL_IMU frames\n", node, interface_name.c_str());
  std::fflush(stdout);

  std::uint32_t write_failures = 0;
  pa::proto::Frame frame;
  while (g_stop == 0) {
    if (!can.read(frame, 200)) {
      if (can.status() == pa::can::SocketCan::Status::io_error) {
        std::fprintf(stderr, "fw_vehicle: error: %s\n", can.message());
        return 1;
      }
      continue;
    }
    vehicle.on_frame(frame, [&](const pa::proto::Frame& out) {
      if (!can.write(out)) ++write_failures;
    });
    fw::posix::ModeChange change;
    while (vehicle.take_mode_change(change)) {
      char age[48] = "no setpoint yet";
      if (change.setpoint_age_us != 0xFFFFFFFFu)
        std::snprintf(age, sizeof age, "the last setpoint %.1f ms old", change.setpoint_age_us * 1e-3);
      std::printf("fw_vehicle: %.3f s: mode %s -> %s (failsafe reason %u), %s\n", change.t_us * 1e-6,
                  pa::proto::mode_name(change.from), pa::proto::mode_name(change.to),
                  static_cast<unsigned>(change.reason), age);
      std::fflush(stdout);
    }
  }
  std::printf("fw_vehicle: stopped (mode %u, %u frames rejected, %u writes failed)\n",
              static_cast<unsigned>(vehicle.vehicle().mode()), vehicle.vehicle().rx_rejected(),
              write_failures);
  return 0;
}
