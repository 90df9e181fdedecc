// hil_can_probe: the plant's side of one vehicle bus, reduced to what proves that `fw_vehicle`
// works on real SocketCAN. It sends HIL_IMU samples (level, at rest) at the IMU rate, waits for
// each sample's HIL_MOTORS, and counts the flight frames the vehicle sends besides. Between two
// clean phases a flood phase puts malformed frames (random identifiers, lengths, payloads) on
// the bus with every sample: the vehicle must keep answering, and answer fully afterwards.
// Exit code 0 when every check holds, 1 otherwise, 2 on bad arguments.
#include <time.h>

#include <cstdint>
#include <cstdio>
#include <iostream>
#include <optional>
#include <random>
#include <string>

#include "pa/command_line.hpp"
#include "pa/constants.hpp"
#include "pa/protocol.hpp"
#include "pa/socketcan.hpp"

namespace {

using namespace pa::proto;

struct Counts {
  unsigned samples = 0;
  unsigned answered = 0;        // samples whose HIL_MOTORS came back
  unsigned motors_running = 0;  // HIL_MOTORS with any motor above zero (the vehicle is disarmed)
  unsigned heartbeats = 0;
  unsigned sessions = 0;
  unsigned telemetry = 0;
  unsigned other = 0;        // frames of other types from this vehicle
  unsigned undecodable = 0;  // frames the protocol rejects (the vehicle must never send one)
  unsigned flood_sent = 0;
  unsigned write_failures = 0;
  double seconds = 0.0;
};

double now_s() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

class Probe {
 public:
  Probe(pa::can::SocketCan& can, std::uint8_t node, std::uint32_t seed)
      : can_(can), node_(node), random_(seed) {}

  // `ticks` samples paced at the IMU rate (lockstep: never faster than the vehicle answers),
  // each followed by `flood` malformed frames.
  Counts run(unsigned ticks, unsigned flood) {
    Counts c;
    const double start = now_s();
    timespec next{};
    clock_gettime(CLOCK_MONOTONIC, &next);
    for (unsigned k = 0; k < ticks; ++k, ++tick_) {
      Frame f;
      encode(HilImuGyro{{0.0f, 0.0f, 0.0f}, tick_}, node_, f);
      send(f, c);
      encode(HilImuAccel{{0.0f, 0.0f, static_cast<float>(pa::kGravity_mps2)}, tick_}, node_, f);
      send(f, c);
      ++c.samples;
      for (unsigned i = 0; i < flood; ++i) {
        send(malformed(), c);
        ++c.flood_sent;
      }
      if (await_motors(c)) ++c.answered;
      next.tv_nsec += static_cast<long>(pa::kImuPeriod_us) * 1000L;
      if (next.tv_nsec >= 1000000000L) {
        next.tv_nsec -= 1000000000L;
        ++next.tv_sec;
      }
      clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next, nullptr);
    }
    c.seconds = now_s() - start;
    return c;
  }

 private:
  void send(const Frame& f, Counts& c) {
    if (!can_.write(f)) ++c.write_failures;
  }

  // Random identifier, length and payload. The plant's own IMU identifiers for this vehicle are
  // left out: a random one would be a valid (if odd) sample, not a malformed frame.
  Frame malformed() {
    Frame f;
    do {
      f.id = static_cast<std::uint16_t>(random_() & 0x7FFu);
    } while (id_node(f.id) == node_ && (id_type(f.id) == static_cast<std::uint8_t>(Type::hil_imu_gyro) ||
                                        id_type(f.id) == static_cast<std::uint8_t>(Type::hil_imu_accel)));
    f.len = static_cast<std::uint8_t>(random_() % 9u);
    for (auto& b : f.data) b = static_cast<std::uint8_t>(random_());
    return f;
  }

  // Reads until this sample's HIL_MOTORS arrives (true) or 500 ms pass (false), counting what
  // the vehicle sends on the way.
  bool await_motors(Counts& c) {
    const double deadline = now_s() + 0.5;
    for (;;) {
      const int wait_ms = static_cast<int>((deadline - now_s()) * 1000.0);
      Frame f;
      if (wait_ms < 0 || !can_.read(f, wait_ms)) return false;
      if (id_node(f.id) != node_) continue;
      Message m;
      if (decode(f, m) != DecodeStatus::ok) {
        ++c.undecodable;
        continue;
      }
      switch (m.type) {
        case Type::hil_motors: {
          for (float v : m.hil_motors.command) {
            if (v != 0.0f) {
              ++c.motors_running;
              break;
            }
          }
          if (m.hil_motors.tick == tick_) return true;
          break;  // a late answer to an earlier sample
        }
        case Type::vehicle_heartbeat: ++c.heartbeats; break;
        case Type::link_session: ++c.sessions; break;
        case Type::telemetry_rates:
        case Type::telemetry_attitude:
        case Type::telemetry_motors:
        case Type::telemetry_status: ++c.telemetry; break;
        default: ++c.other; break;
      }
    }
  }

  pa::can::SocketCan& can_;
  std::uint8_t node_;
  std::mt19937 random_;
  std::uint16_t tick_ = 0;
};

void print(const char* phase, const Counts& c) {
  std::printf(
      "hil_can_probe: %-6s %5u samples, %5u answered with HIL_MOTORS (%u with motors running), %u "
      "VEHICLE_HEARTBEAT, %u LINK_SESSION, %u telemetry, %u other, %u undecodable; %u malformed frames "
      "sent, %u writes failed; %.2f s (%.0f samples/s)\n",
      phase, c.samples, c.answered, c.motors_running, c.heartbeats, c.sessions, c.telemetry, c.other,
      c.undecodable, c.flood_sent, c.write_failures, c.seconds,
      c.seconds > 0.0 ? c.samples / c.seconds : 0.0);
}

bool check(bool ok, const char* what) {
  if (!ok) std::printf("hil_can_probe: FAIL: %s\n", what);
  return ok;
}

// Whether a phase of `c.samples` ticks carried what the vehicle must send: every sample answered
// (at least `min_answered` of them while flooded, when the bus may drop frames), the motors off,
// heartbeats at 50 Hz and the link session at 10 Hz of the vehicle's clock, nothing undecodable.
bool phase_ok(const Counts& c, double min_answered) {
  bool ok = check(c.answered >= min_answered * c.samples, "samples left unanswered");
  ok = check(c.motors_running == 0, "motors running on a disarmed vehicle") && ok;
  ok = check(c.heartbeats * 20 >= c.samples * 9 / 10, "too few VEHICLE_HEARTBEAT frames") && ok;
  ok = check(c.sessions * 100 >= c.samples * 9 / 10, "too few LINK_SESSION frames") && ok;
  return check(c.undecodable == 0, "the vehicle sent undecodable frames") && ok;
}

}  // namespace

int main(int argc, char** argv) {
  std::string interface_name;
  unsigned node = 1;
  unsigned ticks = 2000;
  unsigned flood = 8;
  unsigned seed = 1;
  {
    CLI::App app("", "hil_can_probe");
    pa::cli::describe(app, "usage: hil_can_probe --can IFACE [--node N] [--ticks N] [--flood N] [--seed S]",
                      "Drives one fw_vehicle on a SocketCAN bus with HIL_IMU samples at the IMU rate and\n"
                      "checks its answers: a clean phase, a phase with malformed frames flooding the bus,\n"
                      "and a clean phase again.",
                      "Exit codes: 0 every check held, 1 a check failed or the bus failed, 2 bad arguments.");
    app.add_option("--can", interface_name, "the vehicle's SocketCAN bus (for example vcan1)")
        ->type_name("IFACE")
        ->required()
        ->check(pa::cli::non_empty("needs an interface name"));
    app.add_option("--node", node, "the vehicle's node id, 1..14 (default 1)")
        ->type_name("N")
        ->check(pa::cli::count(kFirstVehicleNode, kLastVehicleNode, "must be 1..14"));
    app.add_option("--ticks", ticks, "samples per clean phase (default 2000; the flood phase has half)")
        ->type_name("N")
        ->check(pa::cli::count(100, 1000000, "needs a count 100..1000000"));
    app.add_option("--flood", flood, "malformed frames per sample in the flood phase (default 8)")
        ->type_name("N")
        ->check(pa::cli::count(1, 1000, "needs a count 1..1000"));
    app.add_option("--seed", seed, "seed of the malformed frames (default 1)")
        ->type_name("S")
        ->check(pa::cli::count(0, 4294967295u, "needs a non-negative integer"));
    if (const std::optional<int> code = pa::cli::parse(app, argc, argv, std::cout, std::cerr)) return *code;
  }

  static pa::can::SocketCan can;
  if (can.open(interface_name.c_str()) != pa::can::SocketCan::Status::ok) {
    std::fprintf(stderr, "hil_can_probe: error: %s\n", can.message());
    return 1;
  }
  Probe probe(can, static_cast<std::uint8_t>(node), seed);
  const Counts before = probe.run(ticks, 0);
  print("clean", before);
  const Counts flooded = probe.run(ticks / 2, flood);
  print("flood", flooded);
  const Counts after = probe.run(ticks, 0);
  print("clean", after);

  bool ok = phase_ok(before, 0.99);
  ok = phase_ok(flooded, 0.9) && ok;
  ok = phase_ok(after, 0.99) && ok;
  std::printf("hil_can_probe: %s\n", ok ? "pass" : "FAIL");
  return ok ? 0 : 1;
}
