// The ground station as a process (`groundstation run`, docs/groundstation.md): the runtime
// (runtime::GroundStation) between the ground CAN bus and the arena's DDS topics. Everything a
// real-time loop does, apart from reading the clock and the socket, is here, so that a test runs
// it with an in-memory bus, in-process DDS and a time of its choosing:
//   on_frame(frame, now)  a frame read from the ground CAN bus;
//   step(now)             operator commands (KILL first, never gated by the mission), the newest
//                         motion-capture frame, the runtime's tick, telemetry when due (fixed
//                         rate), and events for what changed since the last step.
// `now` is the ground clock (CLOCK_MONOTONIC in `groundstation run`, the plant's time with
// --hil-clock).
//
// Motion capture comes in as ROS 2's NamedPoseArray on rt/poses (mocap_conversion.hpp). Its
// header stamp is the time the frame reached the motion-capture node, on that node's clock (the
// system clock, CLOCK_REALTIME, unless it runs on simulated time), not the capture time. The
// estimator wants the capture time on the ground clock, so each frame is placed at
//   stamp - system_offset - latency_s
// where system_offset (set_stamp_offset: the stamp clock minus the ground clock, read by the
// loop) moves the stamp onto the ground clock, and latency_s is what the stamp cannot show: the
// motion-capture system's own latency from exposure to its node (cameras, processing, its SDK),
// told in configuration. The rest, from the node to here (DDS, the network, this loop's step), is
// then in the estimator's prediction to now + command_lead_s like any other delay, and measured
// per frame (stamp to arrival, in the summary). A stamp that the clocks cannot explain (in the
// future, or older than max_stamp_age_s: the two hosts' clocks are not synchronised) is counted,
// and the frame is placed at its arrival time less latency_s instead.
//
// What the process publishes is ROS 2's and pa_msgs' (docs/dds.md), stamped with ROS time: the
// ground clock plus the same system offset. Operator commands (pa_msgs' OperatorCommand on
// rt/pa/operator_commands): TAKE_OFF, LAND and ABORT act on both vehicles (target 0); THROW starts
// an attempt with the target (default vehicle 1) as the thrower; KILL goes to the target or to
// both. Each command is answered with one event, COMMAND_ACCEPTED or COMMAND_REFUSED, whose detail
// begins "command <sequence number>:". A sequence number is acted
// on once (a repeat is refused), except KILL, which is always sent again. Only a target that is
// no vehicle of the act is refused to a KILL.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

#include "groundstation/dds/dds.hpp"
#include "groundstation/dds/mocap_conversion.hpp"
#include "groundstation/dds/pa_msgs.hpp"
#include "groundstation/dds/ros2_telemetry.hpp"
#include "groundstation/link/frame_bus.hpp"
#include "groundstation/runtime/ground_station.hpp"

namespace gs::service {

struct MocapInputConfig {
  dds::MocapBodyNames names;
  // Exposure to the node's stamp. The HIL's motion capture stamps 10 ms after the capture (its
  // default latency, hil/plant/plant_config.hpp); camera systems at 200 Hz report a few ms
  // (Vicon's SDK: GetLatencyTotal; OptiTrack's: the frame's latency field): measure the arena's.
  double latency_s = 0.010;
  double clock_step_s = 0.001;  // --hil-clock: the plant's step, one HIL_CLOCK each
  double max_stamp_age_s = 0.5;
  // A stamp this far after the step's time is still believed: a frame can arrive between the
  // loop's reading of the clock and its take (a descheduled loop: in a slow HIL guest, measured
  // up to tens of ms), while clocks that disagree are off by far more.
  double max_stamp_lead_s = 0.050;
};

struct ProcessConfig {
  double telemetry_period_s = 0.02;  // vehicle and pole telemetry at 50 Hz
  MocapInputConfig mocap;
};

struct ProcessCounters {
  std::uint64_t can_frames = 0;
  std::uint64_t mocap_frames = 0;
  std::uint64_t mocap_unknown_bodies = 0;    // names none of MocapBodyNames (or overlong)
  std::uint64_t mocap_invalid_poses = 0;     // non-finite, NaN or non-unit quaternions
  std::uint64_t mocap_duplicate_bodies = 0;  // a body twice in a frame
  std::uint64_t mocap_excess_poses = 0;      // beyond dds::kMaxPoses in a frame
  std::uint64_t mocap_implausible_stamps = 0;
  double mocap_delay_sum_s = 0.0;  // stamp to arrival, over the frames whose stamp was believed
  double mocap_delay_max_s = 0.0;
  std::uint64_t commands_accepted = 0;
  std::uint64_t commands_refused = 0;
  std::uint64_t kills = 0;
  std::uint64_t telemetry_published = 0;  // samples, vehicles and pole
  std::uint64_t ros_poses_published = 0;  // PoseStamped on rt/pa/.../pose
  std::uint64_t events_published = 0;
};

class Process {
 public:
  // Builds the runtime (plans the throw: tens of milliseconds) and the DDS readers and writers.
  // Throws what GroundStation's constructor throws, and gs::dds::DdsError.
  Process(link::FrameBus& bus, const dds::Participant& participant,
          const runtime::GroundStationConfig& config, const ProcessConfig& process = {});

  void on_frame(const pa::proto::Frame& frame, double now_s);
  // The motion-capture stamps' clock minus the ground clock, in nanoseconds (0 when the stamps
  // are on the ground clock, as the HIL plant's are with --hil-clock). ROS's time: the ROS 2
  // topics the process publishes are stamped on the same clock.
  void set_stamp_offset(std::int64_t offset_ns) { stamp_offset_ns_ = offset_ns; }
  void step(double now_s);
  // On the plant's clock (groundstation run --hil-clock): takes motion-capture frames, waiting up
  // to `timeout` on the wall clock, until `frames` of them have come, so that a step acts on the
  // frames the plant delivered by then whatever DDS's delivery took. NamedPoseArray has no frame
  // number, so frames are counted, and the stamps (the plant's time there) tell a frame published
  // at this clock's step or after: taking one ends the wait, as all before it are in, and sets
  // the count right. False when they did not come in time, and the count then takes the plant's
  // (a frame lost costs one wait).
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
  void act_on(const dds::OperatorCommand& command, double now_s);
  void answer(const dds::OperatorCommand& command, bool accepted, const std::string& detail, double now_s);
  void take_mocap(double now_s);
  void on_mocap(const dds::NamedPoseArray& message, double now_s);
  // ROS time at ground time now_s: what every sample the process writes is stamped with.
  std::int64_t ros_time_ns(double now_s) const;
  void publish_telemetry(double now_s);
  void publish_changes(double now_s);
  void publish(std::uint8_t kind, std::optional<pa::VehicleId> vehicle, const std::string& detail,
               double now_s);
  bool seen_before(std::uint32_t sequence_number);

  runtime::GroundStation station_;
  ProcessConfig config_;
  dds::Reader<dds::NamedPoseArray> mocap_;
  dds::Reader<dds::OperatorCommand> commands_;
  std::array<dds::Writer<dds::VehicleTelemetry>, 2> vehicle_telemetry_;  // by pa::act_slot()
  dds::Writer<dds::PoleTelemetry> pole_telemetry_;
  dds::Writer<dds::Event> events_;
  std::array<dds::Writer<dds::PoseStamped>, 2> vehicle_poses_;  // by pa::act_slot()
  dds::Writer<dds::PoseStamped> pole_pose_;

  std::optional<double> next_telemetry_s_;
  std::uint64_t mocap_counted_ = 0;     // frames taken, for await_mocap
  std::optional<double> last_stamp_s_;  // the latest frame's stamp on the ground clock
  std::int64_t stamp_offset_ns_ = 0;
  std::string first_unknown_body_;
  pa::VehicleId thrower_ = pa::kVehicle1;   // of the latest attempt
  std::array<VehicleSeen, 2> seen_{};       // by pa::act_slot()
  std::array<bool, 2> waiting_for_pole_{};  // as last published (event_pole_wanted), by pa::act_slot()
  int launch_published_ = 0;                // the attempt number whose launch was published
  std::size_t attempts_published_ = 0;
  // The latest sequence numbers acted on (a ring): an operator console's retry is not acted on twice.
  std::array<std::uint32_t, 64> recent_{};
  std::size_t recent_count_ = 0;
  std::size_t recent_next_ = 0;
  ProcessCounters counters_;
};

// The name of an operator command as `groundstation op` spells it ("take-off", "throw", ...).
std::string command_name(std::uint8_t kind);
std::optional<std::uint8_t> command_from_name(const std::string& name);
// The detail an answer to `sequence_number` begins with: "command 17:".
std::string answer_prefix(std::uint32_t sequence_number);

}  // namespace gs::service
