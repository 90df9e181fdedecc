// The ground station as a process (`groundstation run`, docs/groundstation.md): the runtime
// (runtime::GroundStation) between the ground CAN bus and the arena's DDS topics. Everything a
// real-time loop does, apart from reading the clock and the socket, is here, so that a test runs
// it with an in-memory bus, in-process DDS and a time of its choosing:
//   on_frame(frame, now)  a frame read from the ground CAN bus;
//   step(now)             operator commands (KILL first, never gated by the mission), the newest
//                         motion-capture frame, the runtime's tick, telemetry when due (fixed
//                         rate), and events for what changed since the last step.
// `now` is the ground clock, the one the motion capture stamps its frames with (on one host,
// CLOCK_MONOTONIC).
//
// Operator commands (pa_operator_commands): take_off, land and abort act on both vehicles (target
// 0); throw starts an attempt with the target (default vehicle 1) as the thrower; kill goes to
// the target or to both. Each command is answered with one event, command_accepted or
// command_refused, whose detail begins "command <sequence number>:". A sequence number is acted
// on once (a repeat is refused), except KILL, which is always sent again. Only a target that is
// no vehicle of the act is refused to a KILL.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

#include "groundstation/dds/dds.hpp"
#include "groundstation/link/frame_bus.hpp"
#include "groundstation/runtime/ground_station.hpp"

namespace gs::service {

struct ProcessConfig {
  double telemetry_period_s = 0.02;  // vehicle and pole telemetry at 50 Hz
};

struct ProcessCounters {
  std::uint64_t can_frames = 0;
  std::uint64_t mocap_frames = 0;
  std::uint64_t mocap_unknown_bodies = 0;
  std::uint64_t commands_accepted = 0;
  std::uint64_t commands_refused = 0;
  std::uint64_t kills = 0;
  std::uint64_t telemetry_published = 0;  // samples, vehicles and pole
  std::uint64_t events_published = 0;
};

class Process {
 public:
  // Builds the runtime (plans the throw: tens of milliseconds) and the DDS readers and writers.
  // Throws what GroundStation's constructor throws, and gs::dds::DdsError.
  Process(link::FrameBus& bus, const dds::Participant& participant,
          const runtime::GroundStationConfig& config, const ProcessConfig& process = {});

  void on_frame(const pa::proto::Frame& frame, double now_s);
  void step(double now_s);
  // On the plant's clock (groundstation run --hil-clock): takes motion-capture frames, waiting up
  // to `timeout` on the wall clock, until it has the one numbered `frames` - 1 or a later one
  // (none for 0), so that a step acts on the frames the plant delivered by then whatever DDS's
  // delivery took. False when it did not come in time.
  bool await_mocap(std::uint64_t frames, double now_s, std::chrono::nanoseconds timeout);

  const runtime::GroundStation& ground_station() const { return station_; }
  const ProcessCounters& counters() const { return counters_; }
  // A few lines for the end of a run: frames, commands, attempts, the link's counters.
  std::string summary() const;

 private:
  struct VehicleSeen {
    bool heard = false;
    bool lost = true;
    pa::proto::FailsafeReason failsafe = pa::proto::FailsafeReason::none;
  };

  void take_commands(double now_s);
  void act_on(const pa_arena_OperatorCommand& command, double now_s);
  void answer(const pa_arena_OperatorCommand& command, bool accepted, const std::string& detail,
              double now_s);
  void take_mocap(double now_s);
  void on_mocap(const pa_arena_MocapFrame& message, double now_s);
  void publish_telemetry(double now_s);
  void publish_changes(double now_s);
  void publish(pa_arena_EventKind kind, std::optional<pa::VehicleId> vehicle, const std::string& detail,
               double now_s);
  bool seen_before(std::uint32_t sequence_number);

  runtime::GroundStation station_;
  ProcessConfig config_;
  dds::Reader<pa_arena_MocapFrame> mocap_;
  dds::Reader<pa_arena_OperatorCommand> commands_;
  dds::Writer<pa_arena_VehicleTelemetry> vehicle_telemetry_;
  dds::Writer<pa_arena_PoleTelemetry> pole_telemetry_;
  dds::Writer<pa_arena_Event> events_;

  std::optional<double> next_telemetry_s_;
  std::optional<std::uint64_t> newest_mocap_;  // the latest frame number taken
  pa::VehicleId thrower_ = pa::kVehicle1;      // of the latest attempt
  std::array<VehicleSeen, 2> seen_{};          // by pa::act_slot()
  int launch_published_ = 0;                   // the attempt number whose launch was published
  std::size_t attempts_published_ = 0;
  // The latest sequence numbers acted on (a ring): an operator console's retry is not acted on twice.
  std::array<std::uint32_t, 64> recent_{};
  std::size_t recent_count_ = 0;
  std::size_t recent_next_ = 0;
  ProcessCounters counters_;
};

// The name of an operator command as `groundstation op` spells it ("take-off", "throw", ...).
std::string command_name(pa_arena_CommandKind kind);
std::optional<pa_arena_CommandKind> command_from_name(const std::string& name);
// The detail an answer to `sequence_number` begins with: "command 17:".
std::string answer_prefix(std::uint32_t sequence_number);

}  // namespace gs::service
