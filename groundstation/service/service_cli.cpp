// `groundstation run`, `op` and `watch` (docs/groundstation.md): the ground station as a
// real-time process between the vehicles (the ground CAN bus, or each vehicle's serial radio) and
// the arena's DDS topics, an operator's one-shot command, and a live status view. The loop's work
// is in Process (process.hpp); this file holds only what a test cannot drive: the clock, the bus,
// signals and the terminal.
#include <limits.h>
#include <stdlib.h>
#include <sys/random.h>
#include <time.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "groundstation/apps/commands.hpp"
#include "groundstation/link/link_budget.hpp"
#include "groundstation/service/process.hpp"
#include "groundstation/service/radio_bus.hpp"
#include "groundstation/service/socketcan_bus.hpp"
#include "groundstation/service/status_view.hpp"
#include "pa/command_line.hpp"
#include "pa/constants.hpp"
#include "pa/link_key_file.hpp"

namespace gs::apps {
namespace {

using namespace std::chrono_literals;

// Exit codes of op and watch beyond the tools' 0 and 2.
constexpr int kExitRefused = 1;
constexpr int kExitNoAnswer = 3;

// The loop's period between steps. The motion capture arrives every 5 ms; a step every 1 ms acts
// on a frame at most 1 ms after it arrived, and KILL as soon.
constexpr int kStepPeriodMs = 1;

volatile std::sig_atomic_t g_stop = 0;
void on_signal(int) { g_stop = 1; }

double monotonic_s() {
  timespec t{};
  clock_gettime(CLOCK_MONOTONIC, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// CLOCK_REALTIME minus CLOCK_MONOTONIC: ROS stamps are on the system clock, the loop runs on the
// monotonic one. Read at every step, so that a system clock that NTP steps or slews moves with it.
std::int64_t system_minus_monotonic_ns() {
  timespec real{};
  timespec mono{};
  clock_gettime(CLOCK_REALTIME, &real);
  clock_gettime(CLOCK_MONOTONIC, &mono);
  return (static_cast<std::int64_t>(real.tv_sec) - static_cast<std::int64_t>(mono.tv_sec)) * 1'000'000'000 +
         (static_cast<std::int64_t>(real.tv_nsec) - static_cast<std::int64_t>(mono.tv_nsec));
}

void add_domain_option(CLI::App& app, unsigned& domain) {
  app.add_option("--domain", domain, "the DDS domain id of the arena, 0..230")
      ->type_name("D")
      ->required()
      ->check(pa::cli::count(0, 230, "needs a domain id 0..230"));
}

// On CLOCK_MONOTONIC, the clock the motion capture stamps its frames with: a step every
// kStepPeriodMs, and every frame read between the steps. Returns the exit code.
int run_on_monotonic_clock(service::GroundBus& bus, service::Process& process) {
  double next_step_s = monotonic_s();
  pa::proto::Frame frame;
  while (g_stop == 0) {
    const double wait_s = next_step_s - monotonic_s();
    // Rounded up: a wait cut to 0 ms would spin on the socket until the step is due.
    const int timeout_ms = wait_s > 0.0 ? static_cast<int>(std::ceil(wait_s * 1000.0)) : 0;
    // One frame per turn, then the step if it is due: a busy bus delays a step by one frame's
    // handling at most, never starves it.
    if (bus.read(frame, timeout_ms)) {
      process.on_frame(frame, monotonic_s());
    } else if (bus.failed()) {
      return 1;
    }
    const double now_s = monotonic_s();
    if (now_s < next_step_s) continue;
    process.set_stamp_offset(system_minus_monotonic_ns());
    process.step(now_s);
    next_step_s += kStepPeriodMs * 1e-3;
    if (next_step_s < now_s) next_step_s = now_s;  // after a stall, no burst of steps
  }
  return 0;
}

// The HIL plant's clock (hil run --ground-clock, docs/hil.md): each HIL_CLOCK is a step at the
// plant's time, once the motion-capture frames it counts are in; HIL_CLOCK_DONE tells the plant
// it may step on. Frames read in between carry the latest step's time. Returns the exit code.
int run_on_plant_clock(service::GroundBus& bus, service::Process& process, std::uint64_t& late_mocap) {
  // The plant publishes the motion capture before it sends the HIL_CLOCK that counts it; DDS on
  // one host delivers it in microseconds, so a frame missing this long was lost.
  constexpr auto kMocapWait = 1s;
  constexpr double kPlantStep_s = 1.0 / pa::kImuRate_Hz;
  double now_s = 0.0;
  std::optional<std::uint32_t> last_step;
  pa::proto::Frame frame;
  while (g_stop == 0) {
    if (!bus.read(frame, 100)) {
      if (bus.failed()) return 1;
      continue;
    }
    pa::proto::Message m;
    if (pa::proto::id_type(frame.id) != static_cast<std::uint8_t>(pa::proto::Type::hil_clock) ||
        pa::proto::decode(frame, m) != pa::proto::DecodeStatus::ok) {
      process.on_frame(frame, now_s);
      continue;
    }
    // A clock the plant sent again (our answer was late) is answered again, not stepped twice.
    if (m.hil_clock.step != last_step) {
      last_step = m.hil_clock.step;
      now_s = kPlantStep_s * m.hil_clock.step;
      if (!process.await_mocap(m.hil_clock.mocap_frames, now_s, kMocapWait)) ++late_mocap;
      process.step(now_s);
    }
    pa::proto::Frame done;
    pa::proto::encode(pa::proto::HilClockDone{m.hil_clock.step}, pa::proto::kGroundNode, done);
    bus.send(done);
  }
  return 0;
}

// "1=/dev/ttyUSB0": a vehicle of the act and its radio's port.
std::optional<service::RadioPort> radio_port(const std::string& text) {
  const std::size_t eq = text.find('=');
  if (eq == std::string::npos || eq + 1 >= text.size()) return std::nullopt;
  const std::string node = text.substr(0, eq);
  if (node.size() != 1 || node[0] < '0' || node[0] > '9') return std::nullopt;
  const pa::VehicleId vehicle(static_cast<std::uint8_t>(node[0] - '0'));
  if (!pa::is_act_vehicle(vehicle)) return std::nullopt;
  return service::RadioPort{vehicle, text.substr(eq + 1)};
}

// A sequence number no earlier `op` is likely to have used: the ground station acts on each once.
std::uint32_t fresh_sequence_number() {
  std::uint32_t n = 0;
  if (getrandom(&n, sizeof n, 0) != static_cast<ssize_t>(sizeof n))
    n = static_cast<std::uint32_t>(std::chrono::steady_clock::now().time_since_epoch().count());
  return n;
}

}  // namespace

int cmd_run(int argc, char** argv) {
  std::string interface_name;
  unsigned domain = 0;
  std::string key_paths[2];
  std::string store_path;
  double telemetry_hz = 50.0;
  bool hil_clock = false;
  service::MocapInputConfig mocap;
  CLI::App app("", "groundstation run");
  pa::cli::describe(
      app,
      "usage: groundstation run (--can IFACE | --radio N=PORT... [--baud B]) --domain D --key1 FILE --key2 FILE\n"
      "       [--store FILE] [--hil-clock]\n"
      "       [--mocap-vehicle1 NAME] [--mocap-vehicle2 NAME] [--mocap-pole NAME] [--mocap-latency S]\n"
      "       [--arena-volume XMIN YMIN ZMIN XMAX YMAX ZMAX]",
      "Runs the ground station: the vehicles on the ground CAN bus or each on its serial radio\n"
      "(docs/arena.md), the motion capture (ROS 2's NamedPoseArray on /poses, as\n"
      "motion_capture_tracking publishes it), operator commands, telemetry and events on the\n"
      "arena's DDS domain (docs/groundstation.md). Ctrl-C ends it with a summary.",
      "Exit codes: 0 ended by a signal, 1 failed (no CAN socket, a radio's port, a DDS error), 2 bad\n"
      "arguments (a radio too slow for the act among them).");
  CLI::Option* can_option =
      app.add_option("--can", interface_name, "the ground SocketCAN bus (for example can0, vcan0)")
          ->type_name("IFACE")
          ->check(pa::cli::non_empty("needs an interface name"));
  std::vector<std::string> radios;
  CLI::Option* radio_option =
      app.add_option("--radio", radios,
                     "vehicle N's serial radio modem, N=PORT (for example 1=/dev/ttyUSB0); once per vehicle")
          ->type_name("N=PORT")
          ->excludes(can_option);
  can_option->excludes(radio_option);
  unsigned baud = 115200;
  app.add_option("--baud", baud,
                 "the radios' serial rate (default 115200); refused if the act's frames do not fit")
      ->type_name("B")
      ->needs(radio_option);
  add_domain_option(app, domain);
  app.add_option("--key1", key_paths[0], "vehicle 1's link key: a file of 32 hex digits")
      ->type_name("FILE")
      ->required()
      ->check(pa::cli::non_empty("needs a file name"));
  app.add_option("--key2", key_paths[1], "vehicle 2's link key: a file of 32 hex digits")
      ->type_name("FILE")
      ->required()
      ->check(pa::cli::non_empty("needs a file name"));
  app.add_option("--store", store_path, "the adaptation store (SQLite); without it, learning is not kept")
      ->type_name("FILE");
  app.add_option("--telemetry-hz", telemetry_hz, "telemetry rate (default 50)")
      ->type_name("HZ")
      ->check(pa::cli::number_in(1.0, 200.0, "needs a rate 1..200 Hz"));
  const auto body_name = [&app](const char* flag, std::string& name, const char* what) {
    app.add_option(flag, name,
                   std::string("the motion-capture body name of ") + what + " (default " + name + ")")
        ->type_name("NAME")
        ->check(pa::cli::non_empty("needs a body name"));
  };
  body_name("--mocap-vehicle1", mocap.names.vehicle1, "vehicle 1");
  body_name("--mocap-vehicle2", mocap.names.vehicle2, "vehicle 2");
  body_name("--mocap-pole", mocap.names.pole, "the pole (its body z-axis along the pole)");
  app.add_option("--mocap-latency", mocap.latency_s,
                 "seconds from a frame's exposure to its stamp at the motion-capture node (default 0.010)")
      ->type_name("S")
      ->check(pa::cli::number_in(0.0, 0.2, "needs 0..0.2 s"));
  std::vector<double> volume;
  app.add_option(
         "--arena-volume", volume,
         "the arena's volume, a box in the motion capture's coordinates: XMIN YMIN ZMIN XMAX YMAX ZMAX "
         "(m); throws that would leave it are refused (default: not checked)")
      ->expected(6)
      ->type_name("M");
  app.add_flag("--hil-clock", hil_clock,
               "run on a HIL plant's time, a step per HIL_CLOCK frame (hil run --ground-clock), not on "
               "CLOCK_MONOTONIC")
      ->excludes(radio_option);  // the plant's clock comes on the ground CAN bus
  if (const std::optional<int> code = pa::cli::parse(app, argc, argv, std::cout, std::cerr)) return *code;

  if (const std::string problem = dds::check_body_names(mocap.names); !problem.empty()) {
    std::fprintf(stderr, "groundstation run: error: %s\n", problem.c_str());
    return 2;
  }
  if (interface_name.empty() && radios.empty()) {
    std::fprintf(stderr,
                 "groundstation run: error: needs the vehicles' bus: --can IFACE or --radio N=PORT\n");
    return 2;
  }
  std::vector<service::RadioPort> radio_ports;
  for (const std::string& radio : radios) {
    const std::optional<service::RadioPort> port = radio_port(radio);
    if (!port) {
      std::fprintf(
          stderr,
          "groundstation run: error: --radio %s: needs N=PORT with N a vehicle of the act (1 or 2) and a "
          "port, for example 1=/dev/ttyUSB0\n",
          radio.c_str());
      return 2;
    }
    for (const service::RadioPort& other : radio_ports) {
      // The same port twice would split its bytes between two readers: noise on both.
      char a[PATH_MAX], b[PATH_MAX];
      const bool same_port = ::realpath(port->path.c_str(), a) != nullptr &&
                             ::realpath(other.path.c_str(), b) != nullptr && std::strcmp(a, b) == 0;
      if (other.vehicle == port->vehicle || same_port) {
        std::fprintf(
            stderr, "groundstation run: error: --radio %s: %s\n", radio.c_str(),
            same_port ? "that port is another vehicle's radio already" : "that vehicle has a radio already");
        return 2;
      }
    }
    radio_ports.push_back(*port);
  }
  runtime::GroundStationConfig config;
  config.adaptation_store_path = store_path;
  if (!volume.empty()) {
    runtime::ArenaVolume box;
    box.min_m = Eigen::Vector3d(volume[0], volume[1], volume[2]);
    box.max_m = Eigen::Vector3d(volume[3], volume[4], volume[5]);
    const Eigen::Vector3d inner = box.max_m - box.min_m - 2.0 * box.margin_m * Eigen::Vector3d::Ones();
    if (!box.min_m.allFinite() || !box.max_m.allFinite() || (inner.array() <= 0.0).any()) {
      std::fprintf(stderr,
                   "groundstation run: error: --arena-volume needs XMIN YMIN ZMIN XMAX YMAX ZMAX with each "
                   "maximum more than %.1f m above its minimum (the margin from each wall)\n",
                   2.0 * box.margin_m);
      return 2;
    }
    config.arena_volume = box;
  }
  for (const pa::VehicleId v : pa::kActVehicles) {
    link::VehicleKey key{v, {}};
    std::string error;
    if (!pa::auth::read_key_file(key_paths[pa::act_slot(v)], key.key, error)) {
      std::fprintf(stderr, "groundstation run: error: %s\n", error.c_str());
      return 2;
    }
    config.link.keys.push_back(key);
  }
  // Every run its own session token, so that a vehicle never takes an earlier run's frames.
  if (getrandom(&config.link.session, sizeof config.link.session, 0) !=
      static_cast<ssize_t>(sizeof config.link.session)) {
    std::fprintf(stderr, "groundstation run: error: no entropy for the link session (getrandom failed)\n");
    return 1;
  }

  try {
    // The bus first: without it there is nothing to fly, and its message says how to get one.
    std::unique_ptr<service::GroundBus> bus_owner;
    if (radio_ports.empty()) {
      bus_owner = std::make_unique<service::SocketCanBus>(interface_name);
    } else {
      if (!service::RadioBus::supported_baud(baud)) {
        std::fprintf(
            stderr,
            "groundstation run: error: --baud %u: not a serial rate (9600, 19200, 38400, 57600, 115200, "
            "230400, 460800, 921600)\n",
            baud);
        return 2;
      }
      // Each radio carries one vehicle's frames: refused when they would not fit its line.
      const link::LinkBudget budget = link::radio_link_budget(baud, pa::kMocapRate_Hz, config.link);
      std::printf("groundstation run: %s\n", link::describe(budget).c_str());
      if (!budget.fits()) {
        std::fprintf(
            stderr,
            "groundstation run: error: the act's frames do not fit a %u-baud radio (%.0f %% and %.0f %% "
            "of its line, at most %.0f %%): set the modems faster\n",
            baud, 100.0 * budget.to_vehicle.utilisation, 100.0 * budget.from_vehicle.utilisation,
            100.0 * link::kMaxRadioUtilisation);
        return 2;
      }
      bus_owner = std::make_unique<service::RadioBus>(radio_ports, baud);
    }
    service::GroundBus& bus = *bus_owner;
    const dds::Domain dds_domain(static_cast<dds_domainid_t>(domain));
    const dds::Participant participant(dds_domain);
    service::ProcessConfig process_config;
    process_config.telemetry_period_s = 1.0 / telemetry_hz;
    process_config.mocap = mocap;
    if (hil_clock) process_config.mocap.clock_step_s = 1.0 / pa::kImuRate_Hz;  // run_on_plant_clock's step
    service::Process process(bus, participant, config, process_config);

    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
    std::string on = interface_name;
    for (const service::RadioPort& port : radio_ports)
      on += (on.empty() ? "" : ", ") +
            ("vehicle " + std::to_string(port.vehicle.node()) + "'s radio " + port.path);
    std::printf("groundstation run: on %s, DDS domain %u, %s\n", on.c_str(), domain,
                hil_clock ? "on the HIL plant's clock" : "on CLOCK_MONOTONIC");
    std::printf(
        "groundstation run: motion capture from %s: vehicle 1 '%s', vehicle 2 '%s', pole '%s', latency to "
        "the stamp %.1f ms\n",
        dds::Topic<dds::NamedPoseArray>::kName, mocap.names.vehicle1.c_str(), mocap.names.vehicle2.c_str(),
        mocap.names.pole.c_str(), 1e3 * mocap.latency_s);
    std::fflush(stdout);

    std::uint64_t late_mocap = 0;
    const int code =
        hil_clock ? run_on_plant_clock(bus, process, late_mocap) : run_on_monotonic_clock(bus, process);
    if (code != 0) std::fprintf(stderr, "groundstation run: error: %s\n", bus.message());
    else std::printf("groundstation run: stopped\n");
    if (hil_clock)
      std::printf("HIL clock: %llu steps whose motion-capture frame did not come within 1 s\n",
                  static_cast<unsigned long long>(late_mocap));
    std::fputs(process.summary().c_str(), stdout);
    std::fputs(bus.summary().c_str(), stdout);
    return code;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "groundstation run: error: %s\n", e.what());
    return 1;
  }
}

int cmd_op(int argc, char** argv) {
  std::string command;
  unsigned vehicle = 0;
  unsigned domain = 0;
  double timeout_s = 2.0;
  CLI::App app("", "groundstation op");
  pa::cli::describe(
      app, "usage: groundstation op <take-off|land|abort|throw|kill> [--vehicle N] --domain D",
      "Sends one operator command to the ground station on DDS domain D and prints its answer.\n"
      "take-off, land and abort act on both vehicles; throw starts an attempt with vehicle N\n"
      "(default 1) throwing; kill stops the motors of vehicle N, or of both without --vehicle.",
      "Exit codes: 0 accepted, 1 refused, 2 bad arguments, 3 no answer (no ground station on the\n"
      "domain, or none within the timeout).");
  app.add_option("command", command, "the command")
      ->required()
      ->check(pa::cli::one_of({"take-off", "land", "abort", "throw", "kill"},
                              "must be take-off, land, abort, throw or kill"));
  app.add_option("--vehicle", vehicle, "the vehicle, 1 or 2")
      ->type_name("N")
      ->check(pa::cli::count(1, 2, "must be 1 or 2"));
  add_domain_option(app, domain);
  app.add_option("--timeout", timeout_s, "seconds to wait for the answer (default 2)")
      ->type_name("S")
      ->check(pa::cli::number_in(0.1, 60.0, "needs 0.1..60 s"));
  if (const std::optional<int> code = pa::cli::parse(app, argc, argv, std::cout, std::cerr)) return *code;

  try {
    const dds::Domain dds_domain(static_cast<dds_domainid_t>(domain));
    const dds::Participant participant(dds_domain);
    dds::Writer<dds::OperatorCommand> commands(participant);
    dds::Reader<dds::Event> events(participant);
    const auto timeout =
        std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::duration<double>(timeout_s));
    const auto end = std::chrono::steady_clock::now() + timeout;
    // The commands topic is volatile: a command written before the ground station's reader has
    // matched would be lost.
    if (!commands.wait_for_readers(1, timeout)) {
      std::fprintf(stderr,
                   "groundstation op: no ground station on DDS domain %u (nothing reads %s within %.1f s)\n",
                   domain, dds::Topic<dds::OperatorCommand>::kName, timeout_s);
      return kExitNoAnswer;
    }
    dds::OperatorCommand c{};
    c.kind = *service::command_from_name(command);
    c.target = static_cast<std::uint8_t>(vehicle);
    c.sequence_number = fresh_sequence_number();
    commands.write(c);

    const std::string prefix = service::answer_prefix(c.sequence_number);
    for (;;) {
      const auto left = end - std::chrono::steady_clock::now();
      if (left <= 0ns) break;
      const dds::Event* e = events.wait_take(left);
      if (e == nullptr) break;
      const bool answer =
          e->kind == dds::event_kind::kCommandAccepted || e->kind == dds::event_kind::kCommandRefused;
      if (!answer || std::string(e->detail).rfind(prefix, 0) != 0) continue;
      const bool accepted = e->kind == dds::event_kind::kCommandAccepted;
      std::printf("%s %s\n", accepted ? "accepted:" : "refused:", e->detail);
      return accepted ? 0 : kExitRefused;
    }
    std::fprintf(stderr, "groundstation op: no answer to %s (sequence number %u) within %.1f s\n",
                 command.c_str(), c.sequence_number, timeout_s);
    return kExitNoAnswer;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "groundstation op: error: %s\n", e.what());
    return 1;
  }
}

int cmd_watch(int argc, char** argv) {
  unsigned domain = 0;
  bool once = false;
  double seconds = 0.0;
  CLI::App app("", "groundstation watch");
  pa::cli::describe(
      app, "usage: groundstation watch --domain D [--once | --seconds S]",
      "Shows the ground station's view of the act on DDS domain D: each vehicle's link, task,\n"
      "mode and estimate, the pole's mode, estimate and catch prediction, and the latest events.\n"
      "Refreshed twice a second until Ctrl-C (or S seconds); --once prints one view and ends.",
      "Exit codes: 0 done, 2 bad arguments, 3 no telemetry (--once: none within 2 s).");
  add_domain_option(app, domain);
  CLI::Option* once_option = app.add_flag(
      "--once", once, "print one view as soon as both vehicles' and the pole's telemetry arrived");
  app.add_option("--seconds", seconds, "watch for this long, then end")
      ->type_name("S")
      ->check(pa::cli::number_in(0.1, 86400.0, "needs 0.1..86400 s"))
      ->excludes(once_option);
  if (const std::optional<int> code = pa::cli::parse(app, argc, argv, std::cout, std::cerr)) return *code;

  try {
    const dds::Domain dds_domain(static_cast<dds_domainid_t>(domain));
    const dds::Participant participant(dds_domain);
    service::StatusWatch watch(participant);
    if (once) {
      // Until both vehicles and the pole have been heard: each topic's reader matches the ground
      // station's writer in its own time, and a best-effort sample before that is not delivered.
      const auto end = std::chrono::steady_clock::now() + 2s;
      while (!watch.view().has_all_telemetry() && std::chrono::steady_clock::now() < end)
        watch.wait_and_take(100ms);
      if (!watch.view().has_telemetry()) {
        std::fprintf(stderr,
                     "groundstation watch: no telemetry on DDS domain %u within 2 s (is `groundstation run` "
                     "running there?)\n",
                     domain);
        return kExitNoAnswer;
      }
      std::fputs(service::render_status(watch.view()).c_str(), stdout);
      return 0;
    }

    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
    const bool terminal = isatty(STDOUT_FILENO) != 0;
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::nanoseconds>(
                                                            std::chrono::duration<double>(seconds));
    auto next_draw = std::chrono::steady_clock::now();
    while (g_stop == 0 && (seconds <= 0.0 || std::chrono::steady_clock::now() < end)) {
      watch.wait_and_take(50ms);
      if (std::chrono::steady_clock::now() < next_draw) continue;
      next_draw += 500ms;
      // On a terminal the view redraws in place; into a file or a pipe it is appended.
      if (terminal) std::fputs("\x1b[H\x1b[2J", stdout);
      std::printf("DDS domain %u\n", domain);
      std::fputs(watch.view().has_telemetry() ? service::render_status(watch.view()).c_str()
                                              : "no telemetry yet (is `groundstation run` running?)\n",
                 stdout);
      if (!terminal) std::fputs("\n", stdout);
      std::fflush(stdout);
    }
    return watch.view().has_telemetry() ? 0 : kExitNoAnswer;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "groundstation watch: error: %s\n", e.what());
    return 1;
  }
}

}  // namespace gs::apps
