// `hil run --ground-can IF --vehicle-can IF1[,IF2] --domain D [...]`: the truth plant as its own
// process between fw_vehicle processes (one per vehicle bus) and `groundstation run` (on the
// ground bus and DDS), docs/hil.md. This file is the edge: the command line, the sockets, the
// clock, DDS and the logs. The stepping itself is hil::run::PlantExchange.
#include <poll.h>
#include <time.h>

#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "groundstation/dds/dds.hpp"
#include "groundstation/dds/event_detail.hpp"
#include "groundstation/dds/mocap_conversion.hpp"
#include "hil/plant/plant_config.hpp"
#include "hil/plant/recorder.hpp"
#include "hil/run/cmd_run.hpp"
#include "hil/run/plant_exchange.hpp"
#include "hil/sil/ground_station_frame.hpp"
#include "hil/trials/trial_config.hpp"
#include "pa/command_line.hpp"
#include "pa/socketcan.hpp"

namespace hil::run {
namespace {

using pa::proto::Frame;

constexpr const char* kUsage =
    "usage: hil run --ground-can IF --vehicle-can IF1[,IF2] --domain D [--seed S] [--plant FILE]\n"
    "               [--lockstep [--ground-clock] | --realtime] [--seconds T] [--log DIR]";

// A firmware that has not answered its sample for this long is sent it again (it may have
// started after the sample went out), and the wait is reported once.
constexpr std::int64_t kResendAfter_ns = 200'000'000;
// A firmware, or a ground station on the plant's clock, that answered before and has not answered
// for this long is gone (killed): the plant steps on without it until it answers again.
constexpr std::int64_t kGoneAfter_ns = 1'000'000'000;

volatile std::sig_atomic_t g_stop = 0;
void on_signal(int) { g_stop = 1; }

std::int64_t clock_ns(clockid_t clock) {
  timespec ts{};
  clock_gettime(clock, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}
std::int64_t monotonic_ns() { return clock_ns(CLOCK_MONOTONIC); }
std::int64_t realtime_ns() { return clock_ns(CLOCK_REALTIME); }

// One bus this process touches, and its candump-format log (what candump -L writes: the wall
// clock, the interface, ID#DATA), replayable with canplayer.
struct Bus {
  std::string name;
  pa::can::SocketCan can;
  std::ofstream log;
  std::uint64_t read = 0;
  std::uint64_t written = 0;
  std::uint64_t write_failures = 0;

  void record(const Frame& f) {
    if (!log.is_open()) return;
    const std::int64_t t = clock_ns(CLOCK_REALTIME);
    char line[64];
    int n =
        std::snprintf(line, sizeof line, "(%lld.%06lld) %s %03X#", static_cast<long long>(t / 1'000'000'000),
                      static_cast<long long>(t % 1'000'000'000 / 1000), name.c_str(), f.id);
    for (std::uint8_t i = 0; i < f.len && n + 3 < static_cast<int>(sizeof line); ++i)
      n += std::snprintf(line + n, sizeof line - static_cast<std::size_t>(n), "%02X", f.data[i]);
    log << line << '\n';
  }
  void write(const Frame& f) {
    if (can.write(f)) {
      ++written;
      record(f);
    } else {
      ++write_failures;
    }
  }
};

std::vector<std::string> split_names(const std::string& text) {
  std::vector<std::string> names;
  std::stringstream in(text);
  std::string name;
  while (std::getline(in, name, ',')) names.push_back(name);
  return names;
}

struct Options {
  std::string ground_can;
  std::vector<std::string> vehicle_can;
  unsigned domain = 0;
  std::uint64_t seed = 1;
  std::string plant_file;
  bool realtime = false;
  bool ground_clock = false;  // the ground station steps on the plant's time (HIL_CLOCK)
  double seconds = 0.0;       // 0: until a signal
  std::string log_dir;
};

class Runner {
 public:
  Runner(const Options& options, PlantExchange& exchange, std::vector<std::unique_ptr<Bus>>& buses,
         gs::dds::Writer<gs::dds::NamedPoseArray>& mocap, gs::dds::Reader<gs::dds::Event>& events,
         std::ofstream* truth)
      : options_(options), exchange_(exchange), buses_(buses), mocap_(mocap), events_(events), truth_(truth) {
    for (const auto& bus : buses_) fds_.push_back(pollfd{bus->can.fd(), POLLIN, 0});
  }

  // Runs until a signal or --seconds; false after a bus failed (the message is printed).
  bool run() {
    const std::int64_t period_ns = static_cast<std::int64_t>(std::llround(exchange_.period_s() * 1e9));
    start_ns_ = monotonic_ns();
    progress_ns_ = start_ns_;
    std::int64_t next_step_ns = start_ns_;
    std::int64_t sample_sent_ns = start_ns_;
    std::int64_t stepped_ns = start_ns_;
    bool wait_reported = false;
    while (g_stop == 0) {
      if (options_.seconds > 0.0 && exchange_.t_s() >= options_.seconds - 1e-9) break;
      const std::int64_t now = monotonic_ns();
      const bool answered = options_.realtime || exchange_.answered();
      if (answered && now >= next_step_ns) {
        step(now);
        sample_sent_ns = now;
        stepped_ns = now;
        wait_reported = false;
        next_step_ns += period_ns;
        // Lockstep is paced no faster than real time and never catches up in a burst: after a
        // stall the plant's time slips behind the clock. Realtime catches up (the plant's time
        // is the clock's).
        if (!options_.realtime && next_step_ns < now) {
          next_step_ns = now;
          ++slips_;
        }
        continue;
      }
      if (!answered && now - stepped_ns > kGoneAfter_ns && release_the_silent(now - stepped_ns)) continue;
      if (!answered && now - sample_sent_ns > kResendAfter_ns) {
        if (!wait_reported) report_wait();
        wait_reported = true;
        exchange_.resend_unanswered();
        write_vehicle_frames();
        write_ground_frames();
        sample_sent_ns = now;
      }
      const std::int64_t until = answered ? next_step_ns : sample_sent_ns + kResendAfter_ns;
      if (!pump(until - monotonic_ns())) return false;
    }
    wall_s_ = static_cast<double>(monotonic_ns() - start_ns_) * 1e-9;
    return true;
  }

  double wall_s() const { return wall_s_; }
  std::uint64_t mocap_published() const { return mocap_published_; }
  std::uint64_t slips() const { return slips_; }

 private:
  void step(std::int64_t now_ns) {
    take_events();
    const std::uint64_t handed = exchange_.poles_handed();
    exchange_.step();
    if (exchange_.poles_handed() != handed) {
      std::printf("hil run: %.3f s: the pole put on the thrower's plate\n", exchange_.t_s());
      std::fflush(stdout);
    }
    write_vehicle_frames();
    // The motion capture before the ground bus, whose last frame is the HIL_CLOCK that has the
    // ground station wait for it.
    publish_mocap();
    write_ground_frames();
    if (exchange_.t_s() >= next_progress_s_ - 1e-9) report_progress(now_ns);
    if (truth_ != nullptr && ++steps_ % 5 == 0) {  // the truth at the motion capture's 200 Hz
      for (const pa::VehicleId v : pa::kActVehicles)
        write_vehicle_truth_row(*truth_, VehicleTruthRow{exchange_.t_s(), v, exchange_.plant().vehicle(v)});
    }
  }

  // The person standing by with the pole reads the ground station's events: an attempt that
  // begins (the operator's throw accepted) asks them to hand the pole up to its thrower at the
  // throw's origin the event names (ATTEMPT), and POLE_WANTED says when the thrower waits for it.
  void take_events() {
    while (const gs::dds::Event* e = events_.take()) {
      const pa::VehicleId vehicle(e->vehicle);
      if (!pa::is_act_vehicle(vehicle)) continue;
      const std::uint8_t kind = e->kind;
      if (kind == gs::dds::event_kind::kPoleWanted) {
        if (const std::optional<bool> waiting = gs::dds::pole_wanted(e->detail)) {
          exchange_.show_waiting_for_pole(vehicle, *waiting);
          std::printf("hil run: %.3f s: vehicle %u %s for the pole\n", exchange_.t_s(),
                      static_cast<unsigned>(vehicle.node()), *waiting ? "waits" : "no longer waits");
          std::fflush(stdout);
        }
        continue;
      }
      const std::optional<Vec3> origin =
          kind == gs::dds::event_kind::kAttempt ? gs::dds::attempt_event_origin(e->detail) : std::nullopt;
      if (!origin) continue;
      exchange_.hand_pole_to(vehicle, *origin);
      std::printf(
          "hil run: %.3f s: a throw by vehicle %u accepted: the pole goes on its plate once it hovers "
          "still at (%.2f, %.2f, %.2f) m\n",
          exchange_.t_s(), static_cast<unsigned>(vehicle.node()), origin->x(), origin->y(), origin->z());
      std::fflush(stdout);
    }
  }

  void write_ground_frames() {
    for (const Frame& f : exchange_.take_ground_frames()) buses_[0]->write(f);
  }

  void write_vehicle_frames() {
    for (std::size_t i = 0; i < exchange_.vehicles(); ++i)
      for (const Frame& f : exchange_.take_vehicle_frames(pa::kActVehicles[i])) buses_[1 + i]->write(f);
  }

  // As motion_capture_tracking publishes: a NamedPoseArray on rt/poses stamped when the frame
  // reached its node, i.e. at its delivery (the capture plus the plant's motion-capture latency),
  // the ground station being told that latency (groundstation run --mocap-latency). The stamp's
  // clock: with --ground-clock the plant's time itself (as ROS's simulated time); otherwise the
  // system clock, as a ROS node's, that long before the clock's present the frame was delivered
  // in the plant, whatever the plant's time lags behind the clock.
  void publish_mocap() {
    for (const CapturedFrame& m : exchange_.take_mocap()) {
      const std::int64_t stamp_ns =
          options_.ground_clock ? gs::dds::to_nanoseconds(m.delivery_t_s)
                                : realtime_ns() - gs::dds::to_nanoseconds(exchange_.t_s() - m.delivery_t_s);
      gs::dds::mocap_frame_to_dds(sil::to_ground_station_frame(m), stamp_ns, body_names_, message_);
      mocap_.write(message_.message());
      ++mocap_published_;
    }
  }

  // How fast the plant ran over the last kProgressEvery_s of its time: the ground station runs
  // on the clock, so a plant far behind it is a different world for the vehicles' link.
  void report_progress(std::int64_t now_ns) {
    const double wall_s = static_cast<double>(now_ns - progress_ns_) * 1e-9;
    std::printf("hil run: %.1f s of plant time, the last %.1f s in %.2f s of the clock (%.2f of real time)\n",
                exchange_.t_s(), kProgressEvery_s, wall_s, wall_s > 0.0 ? kProgressEvery_s / wall_s : 0.0);
    std::fflush(stdout);
    progress_ns_ = now_ns;
    next_progress_s_ += kProgressEvery_s;
  }

  // Lets go of every process that answered before and is silent now; whether there was one.
  bool release_the_silent(std::int64_t silent_ns) {
    const double silent_s = static_cast<double>(silent_ns) * 1e-9;
    bool released = false;
    for (std::size_t i = 0; i < exchange_.vehicles(); ++i) {
      const pa::VehicleId v = pa::kActVehicles[i];
      if (!exchange_.awaiting_vehicle(v) || !exchange_.vehicle_answered_once(v)) continue;
      exchange_.release_vehicle(v);
      released = true;
      std::fprintf(
          stderr,
          "hil run: %.3f s: vehicle %u's firmware has not answered for %.1f s: its motors stop, the plant "
          "steps on without it until it answers again\n",
          exchange_.t_s(), unsigned(v.node()), silent_s);
    }
    if (exchange_.awaiting_ground() && exchange_.ground_clock_counters().answered > 0) {
      exchange_.release_ground();
      released = true;
      std::fprintf(
          stderr,
          "hil run: %.3f s: the ground station has not answered for %.1f s: stepping on without it until "
          "it answers again\n",
          exchange_.t_s(), silent_s);
    }
    return released;
  }

  void report_wait() {
    if (exchange_.awaiting_ground())
      std::fprintf(stderr, "hil run: waiting for the ground station's HIL_CLOCK_DONE on %s (step %llu)\n",
                   buses_[0]->name.c_str(),
                   static_cast<unsigned long long>(std::llround(exchange_.t_s() / exchange_.period_s())));
    for (std::size_t i = 0; i < exchange_.vehicles(); ++i) {
      const pa::VehicleId v = pa::kActVehicles[i];
      const VehicleExchangeCounters c = exchange_.counters(v);
      if (c.answered + c.missed < c.samples_sent)
        std::fprintf(stderr, "hil run: waiting for vehicle %u's HIL_MOTORS on %s (sample %llu)\n",
                     unsigned(v.node()), buses_[1 + i]->name.c_str(),
                     static_cast<unsigned long long>(c.samples_sent - 1));
    }
  }

  // Reads every bus until `wait_ns` passed, handing the frames to the exchange; false when a
  // bus failed.
  bool pump(std::int64_t wait_ns) {
    if (wait_ns < 0) wait_ns = 0;
    const timespec timeout{static_cast<time_t>(wait_ns / 1'000'000'000),
                           static_cast<long>(wait_ns % 1'000'000'000)};
    const int ready = ppoll(fds_.data(), fds_.size(), &timeout, nullptr);
    if (ready < 0) {
      if (errno == EINTR) return true;
      std::fprintf(stderr, "hil run: error: poll on the CAN sockets failed: %s\n", std::strerror(errno));
      return false;
    }
    for (std::size_t b = 0; b < fds_.size(); ++b) {
      if ((fds_[b].revents & POLLIN) == 0) continue;
      Bus& bus = *buses_[b];
      Frame f;
      while (bus.can.read(f, 0)) {
        ++bus.read;
        bus.record(f);
        if (b == 0) exchange_.on_ground_frame(f);
        else exchange_.on_vehicle_frame(pa::kActVehicles[b - 1], f);
      }
      if (bus.can.status() == pa::can::SocketCan::Status::io_error) {
        std::fprintf(stderr, "hil run: error: %s: %s\n", bus.name.c_str(), bus.can.message());
        return false;
      }
    }
    return true;
  }

  const Options& options_;
  PlantExchange& exchange_;
  std::vector<std::unique_ptr<Bus>>& buses_;
  gs::dds::Writer<gs::dds::NamedPoseArray>& mocap_;
  gs::dds::Reader<gs::dds::Event>& events_;
  std::ofstream* truth_;
  std::vector<pollfd> fds_;
  gs::dds::MocapMessage message_;
  const gs::dds::MocapBodyNames body_names_;  // the ground station's defaults
  static constexpr double kProgressEvery_s = 5.0;
  std::int64_t start_ns_ = 0;
  std::int64_t progress_ns_ = 0;
  double next_progress_s_ = kProgressEvery_s;
  std::uint64_t steps_ = 0;
  std::uint64_t mocap_published_ = 0;
  std::uint64_t slips_ = 0;
  double wall_s_ = 0.0;
};

void print_summary(const Options& o, const PlantExchange& exchange, const Runner& runner,
                   const std::vector<std::unique_ptr<Bus>>& buses) {
  const double t = exchange.t_s();
  std::printf("hil run: stopped after %.3f s of plant time in %.3f s (%.2f of real time, %s, %llu slips)\n",
              t, runner.wall_s(), runner.wall_s() > 0.0 ? t / runner.wall_s() : 0.0,
              o.realtime       ? "realtime"
              : o.ground_clock ? "lockstep with the ground station"
                               : "lockstep",
              static_cast<unsigned long long>(runner.slips()));
  if (o.ground_clock) {
    const GroundClockCounters& g = exchange.ground_clock_counters();
    std::printf(
        "hil run: ground clock: %llu HIL_CLOCK sent, %llu answered, %llu other answers, released %llu "
        "times\n",
        static_cast<unsigned long long>(g.clocks_sent), static_cast<unsigned long long>(g.answered),
        static_cast<unsigned long long>(g.other_answers), static_cast<unsigned long long>(g.released));
  }
  for (std::size_t i = 0; i < exchange.vehicles(); ++i) {
    const pa::VehicleId v = pa::kActVehicles[i];
    const VehicleExchangeCounters c = exchange.counters(v);
    const Bus& bus = *buses[1 + i];
    std::printf(
        "hil run: vehicle %u on %s: %llu samples, %llu answered, %llu missed, %llu late answers, %llu resent; "
        "%llu frames read, %llu written (%llu failed); radio up %llu offered, %llu lost, %llu delivered; "
        "down %llu offered, %llu lost, %llu delivered; released %llu times\n",
        unsigned(v.node()), bus.name.c_str(), static_cast<unsigned long long>(c.samples_sent),
        static_cast<unsigned long long>(c.answered), static_cast<unsigned long long>(c.missed),
        static_cast<unsigned long long>(c.late_answers), static_cast<unsigned long long>(c.samples_resent),
        static_cast<unsigned long long>(bus.read), static_cast<unsigned long long>(bus.written),
        static_cast<unsigned long long>(bus.write_failures),
        static_cast<unsigned long long>(c.uplink_offered), static_cast<unsigned long long>(c.uplink_lost),
        static_cast<unsigned long long>(c.uplink_delivered),
        static_cast<unsigned long long>(c.downlink_offered), static_cast<unsigned long long>(c.downlink_lost),
        static_cast<unsigned long long>(c.downlink_delivered), static_cast<unsigned long long>(c.released));
  }
  for (const pa::VehicleId v : pa::kActVehicles) {
    const VehicleTruthSummary& s = exchange.truth_summary(v);
    bool motors_off = true;
    for (double m : exchange.motor_commands(v).command) motors_off = motors_off && m == 0.0;
    std::printf(
        "hil run: vehicle %u truth: highest %.3f m, %.2f s above %.1f m; now at z %.3f m, %s, motors %s\n",
        unsigned(v.node()), s.highest_m, s.airborne_s, VehicleTruthSummary::kAirborneHeight_m,
        exchange.plant().vehicle(v).body.position_m.z(),
        exchange.plant().vehicle_on_floor(v) ? "on the floor" : "off the floor", motors_off ? "off" : "on");
  }
  const Bus& ground = *buses[0];
  std::printf(
      "hil run: ground bus %s: %llu frames read, %llu written (%llu failed), %llu carried by no radio; %llu "
      "motion-capture frames published on DDS domain %u\n",
      ground.name.c_str(), static_cast<unsigned long long>(ground.read),
      static_cast<unsigned long long>(ground.written), static_cast<unsigned long long>(ground.write_failures),
      static_cast<unsigned long long>(exchange.ground_frames_not_carried()),
      static_cast<unsigned long long>(runner.mocap_published()), o.domain);
}

}  // namespace

int cmd_run(int argc, char** argv) {
  Options o;
  std::string vehicle_can;
  bool lockstep = false;
  {
    CLI::App app("", "hil run");
    pa::cli::describe(
        app, kUsage,
        "Runs the truth plant as its own process: each vehicle's firmware is an fw_vehicle process on\n"
        "its vehicle bus (vehicle i on the i-th bus, node i), fed HIL_IMU samples and answering with\n"
        "HIL_MOTORS; a radio model carries the flight frames between each vehicle bus and the ground\n"
        "bus; the motion capture is published on DDS domain D for `groundstation run` (docs/hil.md).",
        "Exit codes: 0 ended by a signal or after --seconds, 1 a bus failed, 2 bad arguments, a\n"
        "missing CAN interface or no CAN sockets.");
    app.add_option("--ground-can", o.ground_can, "the ground bus, where groundstation run listens")
        ->type_name("IF")
        ->required()
        ->check(pa::cli::non_empty("needs an interface name"));
    app.add_option("--vehicle-can", vehicle_can, "each vehicle's bus, comma-separated (vehicle 1's first)")
        ->type_name("IF1[,IF2]")
        ->required()
        ->check(pa::cli::non_empty("needs one or two interface names"));
    app.add_option("--domain", o.domain, "the DDS domain id of the arena, 0..230")
        ->type_name("D")
        ->required()
        ->check(pa::cli::count(0, 230, "needs a domain id 0..230"));
    app.add_option("--seed", o.seed, "seed of the plant's noise and the radios (default 1)")
        ->type_name("S")
        ->check(pa::cli::count(0, UINT64_MAX, "needs a non-negative integer"));
    app.add_option("--plant", o.plant_file, "plant configuration (default: the built-in one)")
        ->type_name("FILE");
    auto* lockstep_flag = app.add_flag(
        "--lockstep", lockstep, "step only when every firmware answered, no faster than real time (default)");
    auto* realtime_flag =
        app.add_flag("--realtime", o.realtime, "step on the clock, whether the firmware answered or not")
            ->excludes(lockstep_flag);
    app.add_flag("--ground-clock", o.ground_clock,
                 "lockstep with the ground station too: it runs on the plant's time (groundstation run "
                 "--hil-clock)")
        ->excludes(realtime_flag);
    app.add_option("--seconds", o.seconds,
                   "stop after T seconds of plant time (default: at SIGINT or SIGTERM)")
        ->type_name("T")
        ->check(pa::cli::number_in(0.001, 1e6, "needs a number of seconds 0.001..1e6"));
    app.add_option("--log", o.log_dir, "write DIR/<bus>.log (candump format) and DIR/truth.csv")
        ->type_name("DIR");
    if (const std::optional<int> code = pa::cli::parse(app, argc, argv, std::cout, std::cerr)) return *code;
  }
  o.vehicle_can = split_names(vehicle_can);
  if (o.vehicle_can.empty() || o.vehicle_can.size() > 2) {
    std::cerr << "hil run: --vehicle-can needs one or two interface names, got '" << vehicle_can << "'\n"
              << kUsage << "\n";
    return 2;
  }
  for (const std::string& name : o.vehicle_can) {
    if (name.empty() || name == o.ground_can) {
      std::cerr << "hil run: --vehicle-can needs names of buses other than the ground bus, got '"
                << vehicle_can << "'\n"
                << kUsage << "\n";
      return 2;
    }
  }

  PlantConfig plant;
  if (!o.plant_file.empty()) {
    std::string error;
    if (!load_plant_config(o.plant_file, plant, error)) {
      std::cerr << "hil run: " << error << "\n";
      return 2;
    }
  }

  // The buses first: without them there is nothing to run, and their messages say how to get them.
  std::vector<std::unique_ptr<Bus>> buses;
  std::vector<std::string> names{o.ground_can};
  names.insert(names.end(), o.vehicle_can.begin(), o.vehicle_can.end());
  for (const std::string& name : names) {
    auto bus = std::make_unique<Bus>();
    bus->name = name;
    if (bus->can.open(name.c_str()) != pa::can::SocketCan::Status::ok) {
      std::fprintf(stderr, "hil run: error: %s\n", bus->can.message());
      return 2;
    }
    buses.push_back(std::move(bus));
  }

  std::ofstream truth;
  if (!o.log_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(o.log_dir, ec);
    if (ec) {
      std::cerr << "hil run: cannot create '" << o.log_dir << "': " << ec.message() << "\n";
      return 1;
    }
    for (auto& bus : buses) {
      bus->log.open(o.log_dir + "/" + bus->name + ".log");
      if (!bus->log) {
        std::cerr << "hil run: cannot write '" << o.log_dir << "/" << bus->name << ".log'\n";
        return 1;
      }
    }
    truth.open(o.log_dir + "/truth.csv");
    if (!truth) {
      std::cerr << "hil run: cannot write '" << o.log_dir << "/truth.csv'\n";
      return 1;
    }
    write_vehicle_truth_header(truth);
  }

  try {
    const trials::SeriesConfig trial = trials::trial_config(plant, o.seed, trials::PlantDraw::as_given);
    PlantExchange exchange(trial.plant, trial.arena.radio, trial.seed, o.vehicle_can.size());
    if (o.ground_clock) exchange.join_ground_clock();
    const gs::dds::Domain domain(static_cast<dds_domainid_t>(o.domain));
    const gs::dds::Participant participant(domain);
    gs::dds::Writer<gs::dds::NamedPoseArray> mocap(participant);
    gs::dds::Reader<gs::dds::Event> events(participant);

    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
    std::printf("hil run: ground bus %s, vehicle buses %s, DDS domain %u, seed %llu, %s\n",
                o.ground_can.c_str(), vehicle_can.c_str(), o.domain, static_cast<unsigned long long>(o.seed),
                o.realtime       ? "realtime"
                : o.ground_clock ? "lockstep with the ground station"
                                 : "lockstep");
    std::fflush(stdout);

    Runner runner(o, exchange, buses, mocap, events, truth.is_open() ? &truth : nullptr);
    const bool ok = runner.run();
    print_summary(o, exchange, runner, buses);
    return ok ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hil run: error: %s\n", e.what());
    return 1;
  }
}

}  // namespace hil::run
