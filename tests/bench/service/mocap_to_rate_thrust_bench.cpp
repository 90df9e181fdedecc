// The ground-station process's own latency (groundstation/service/process.hpp): from the instant
// a motion-capture frame is published on DDS to the instant the Process's bus is handed the first
// RATE_THRUST computed from it. In between: Cyclone's delivery within the process, the take in
// Process::step, the conversion, the estimator update, latency compensation, mission and
// controllers, and the link's signing (its AUTH frame follows at once). Not in it: the wait of up
// to 1 ms for the real loop's next step (`groundstation run`), the CAN socket, the radio.
//
// With vehicles really flying: the lockstep arena (hil/sil/arena.hpp: plant, both firmware cores,
// radios, motion capture) in place of the vehicles and the cameras, as SeriesRunner feeds a bare
// GroundStation (hil/trials/series.cpp), but through the Process: every 1 ms step the arena's ground
// frames go to on_frame, each motion-capture frame it delivered is converted to the DDS sample and
// published (an in-process participant on domain 131, used by no other test), then step() runs,
// and what the Process sent goes to the arena's ground bus. The take-off is an operator command
// on /pa/operator_commands, as `groundstation op take-off` sends it. Measured while both vehicles
// hover (the runtime's task, and above kAirborne_m on the plant's truth), for kHover_s of
// simulated time, one flight per iteration from its own seed; the arena's stepping is not.
//
// The wall clock (steady_clock), under whatever else the machine runs. Printed: latency_median_us,
// latency_p99_us, samples; not_taken (frames a step did not find on the topic) and
// without_rate_thrust (frames taken that sent none) are not samples, and should be 0.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <optional>
#include <vector>

#include "groundstation/dds/mocap_conversion.hpp"
#include "groundstation/service/process.hpp"
#include "hil/sil/arena.hpp"
#include "hil/sil/firmware_vehicle.hpp"
#include "hil/sil/ground_station_frame.hpp"

namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;
using gs::mission::Task;

constexpr double kTakeOffTimeout_s = 10.0;
constexpr double kHover_s = 20.0;    // 4,000 frames at 200 Hz per flight
constexpr double kAirborne_m = 0.5;  // half the take-off height, on the truth

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(p * static_cast<double>(v.size() - 1))];
}

// The Process's ground bus: keeps what it is handed for the arena's radios (carried after the
// step, as the arena's timing contract wants) and stamps the first RATE_THRUST once armed.
class StampingBus final : public gs::link::FrameBus {
 public:
  bool send(const pa::proto::Frame& frame) override {
    if (armed_ && pa::proto::id_type(frame.id) == static_cast<std::uint8_t>(pa::proto::Type::rate_thrust)) {
      sent_ = Clock::now();
      armed_ = false;
    }
    frames_.push_back(frame);
    return true;
  }
  void arm() {
    armed_ = true;
    sent_.reset();
  }
  std::optional<Clock::time_point> sent() const { return sent_; }
  void carry_to(hil::sil::Arena& arena) {
    for (const pa::proto::Frame& f : frames_) arena.send_from_ground(f);
    frames_.clear();
  }

 private:
  std::vector<pa::proto::Frame> frames_;
  bool armed_ = false;
  std::optional<Clock::time_point> sent_;
};

// The ground station holds the keys the arena's firmware was built with.
gs::runtime::GroundStationConfig simulation_keys() {
  gs::runtime::GroundStationConfig c;
  for (const pa::VehicleId v : pa::kActVehicles) c.link.keys.push_back({v, hil::sil::simulation_key(v)});
  return c;
}

// One flight: the arena (from `seed`) and the Process on `participant`, the motion capture and an operator
// console publishing on `outside`.
class Flight {
 public:
  Flight(const gs::dds::Participant& participant, const gs::dds::Participant& outside, std::uint64_t seed)
      : arena_(hil::PlantConfig{}, hil::sil::ArenaConfig{}, seed),
        process_(bus_, participant, simulation_keys()),
        mocap_(outside),
        commands_(outside) {}

  bool connected() { return mocap_.wait_for_readers(1, 5s) && commands_.wait_for_readers(1, 5s); }

  void take_off() {
    gs::dds::OperatorCommand c{};
    c.kind = gs::dds::command_kind::kTakeOff;
    c.sequence_number = 1;
    commands_.write(c);
  }

  bool hovering() const {
    const gs::runtime::GroundStation& gs = process_.ground_station();
    return gs.task(pa::kVehicle1) == Task::hover && gs.task(pa::kVehicle2) == Task::hover;
  }

  // One 1 ms step; each motion-capture frame's latency into `latency_us` when `measure`.
  void step(bool measure, std::vector<double>& latency_us) {
    arena_.step();
    const double now = arena_.t_s();
    for (const pa::proto::Frame& f : arena_.take_ground_frames()) process_.on_frame(f, now);
    const std::vector<hil::CapturedFrame> frames = arena_.take_mocap();
    for (const hil::CapturedFrame& m : frames) {
      // Stamped at delivery, as motion_capture_tracking stamps arrival at its node.
      gs::dds::mocap_frame_to_dds(hil::sil::to_ground_station_frame(m),
                                  gs::dds::to_nanoseconds(m.delivery_t_s), gs::dds::MocapBodyNames{},
                                  message_);
      const std::uint64_t taken = process_.counters().mocap_frames;
      bus_.arm();
      const Clock::time_point published = Clock::now();
      mocap_.write(message_.message());
      process_.step(now);
      if (!measure) continue;
      if (process_.counters().mocap_frames == taken) {
        ++not_taken_;
      } else if (const std::optional<Clock::time_point> sent = bus_.sent()) {
        latency_us.push_back(std::chrono::duration<double, std::micro>(*sent - published).count());
      } else {
        ++without_rate_thrust_;
      }
    }
    if (frames.empty()) process_.step(now);
    bus_.carry_to(arena_);
  }

  double t_s() const { return arena_.t_s(); }
  // On the plant's truth: both vehicles above `height_m`.
  bool airborne(double height_m) const {
    for (const pa::VehicleId v : pa::kActVehicles)
      if (arena_.plant().vehicle(v).body.position_m.z() < height_m) return false;
    return true;
  }
  std::uint64_t not_taken() const { return not_taken_; }
  std::uint64_t without_rate_thrust() const { return without_rate_thrust_; }

 private:
  hil::sil::Arena arena_;
  StampingBus bus_;
  gs::service::Process process_;
  gs::dds::Writer<gs::dds::NamedPoseArray> mocap_;
  gs::dds::Writer<gs::dds::OperatorCommand> commands_;
  gs::dds::MocapMessage message_;
  std::uint64_t not_taken_ = 0;
  std::uint64_t without_rate_thrust_ = 0;
};

void BM_MocapToRateThrustLatency(benchmark::State& state) {
  gs::dds::Domain domain(131, gs::dds::in_process_config());
  gs::dds::Participant station_side(domain);
  gs::dds::Participant outside(domain);
  std::vector<double> latency_us;
  std::uint64_t not_taken = 0, without_rate_thrust = 0, seed = 0;
  double simulated_s = 0.0;
  for (auto _ : state) {
    Flight flight(station_side, outside, ++seed);
    if (!flight.connected()) {
      state.SkipWithError("the Process's readers did not match");
      return;
    }
    flight.take_off();
    const double give_up = flight.t_s() + kTakeOffTimeout_s;
    while (!flight.hovering() && flight.t_s() < give_up) flight.step(false, latency_us);
    if (!flight.hovering()) {
      state.SkipWithError("the vehicles did not take off");
      return;
    }
    const double until = flight.t_s() + kHover_s;
    while (flight.t_s() < until && flight.hovering()) flight.step(true, latency_us);
    if (!flight.hovering() || !flight.airborne(kAirborne_m)) {
      state.SkipWithError("the vehicles did not keep hovering");
      return;
    }
    simulated_s += flight.t_s();
    not_taken += flight.not_taken();
    without_rate_thrust += flight.without_rate_thrust();
  }
  state.counters["latency_median_us"] = percentile(latency_us, 0.5);
  state.counters["latency_p99_us"] = percentile(latency_us, 0.99);
  state.counters["samples"] = static_cast<double>(latency_us.size());
  state.counters["simulated_s"] = simulated_s;
  state.counters["not_taken"] = static_cast<double>(not_taken);
  state.counters["without_rate_thrust"] = static_cast<double>(without_rate_thrust);
}
BENCHMARK(BM_MocapToRateThrustLatency)->Unit(benchmark::kMillisecond)->Iterations(5)->UseRealTime();

}  // namespace
