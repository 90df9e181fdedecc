// The ground side of the compact CAN protocol (docs/protocol.md) for a few vehicles: the
// ground heartbeat, setpoints, commands with acknowledgement and retry, KILL, clock
// synchronisation, and what the vehicles report (heartbeat, IMPACT, telemetry).
//
// No clocks, no threads: the ground time now_s (seconds) is always passed in. The caller
// calls tick() often (at least at the heartbeat rate, 50 Hz; the control loop's 200 Hz is
// fine), hands every frame read from the ground bus to on_frame(), and sends setpoints, commands
// and KILLs when it wants. Frames go out through a FrameBus. Every frame is encoded and decoded
// by pa::proto (shared/include/pa/protocol.hpp); frames that do not decode, come from a node
// this link does not talk to, or travel the other way are counted and dropped, never asserted on.
//
// State is fixed once constructed: per vehicle a bounded command table, a bounded list of
// outstanding TIMESYNC requests and a ring of heartbeat arrival times; one bounded impact
// queue. A flood of frames costs counters, not memory; on_frame() does not allocate.
//
// What the vehicle requires (firmware/core: fw::CommandLink, fw::Supervisor, fw::Vehicle):
// - Authentication (pa/link_auth.hpp, docs/security.md): every frame to a vehicle is followed
//   by its AUTH frame, signed with the vehicle's key (GroundLinkConfig::keys) in the session the
//   vehicle announced in its latest LINK_SESSION. Until one has been heard (within 100 ms of the
//   vehicle's boot or of this link's start) nothing can be sent to it and frames are counted as
//   unsigned. There are no broadcasts: the heartbeat and KILL-all go to each vehicle.
// - Session: the vehicle adopts the session token of the GS_HEARTBEATs it hears while on the
//   ground with its motors off (disarmed or landed) and refuses a COMMAND with any other token (bad_session_token). So at least one heartbeat
//   must have reached it before the first command: call tick() first and give it the radio's
//   latency. Two ground stations with different sessions make a grounded vehicle follow the
//   latest one. KILL carries the token but is honoured whatever it is.
// - Heartbeat watchdog: the vehicle counts the ground's heartbeats live for 300 ms after the
//   last one with a newer sequence. Armed without them it disarms; flying it goes to a failsafe
//   hover, then descends. Keep calling tick().
// - ARM: accepted only from disarmed (DISARM first after a KILL or a landing), with a live
//   heartbeat, a healthy IMU, and the vehicle's LATEST ACCEPTED setpoint at zero thrust (it need
//   not be fresh; before the first setpoint it is zero). Send send_setpoint(node, {0 thrust, 0
//   rates}) first whenever the vehicle may hold a non-zero one; note that VehicleInput's default
//   thrust is g, not zero. Armed, the motors idle until a fresh setpoint asks for more than the
//   take-off thrust (2 m/s^2), which makes it fly.
// - Flying, the setpoints must keep coming with new sequence numbers: a stream older than 20 ms
//   is stale and the vehicle hovers level on its own (failsafe), then descends. Each
//   send_setpoint() uses the next sequence; repeating an old frame does not refresh the stream.
// - The vehicle does not recognise a retried COMMAND as a duplicate: it executes it again. So
//   when the ack of an accepted ARM is lost, the retry is refused with not_disarmed and the
//   ack's mode armed; the link reports that as accepted (an earlier attempt armed it, see
//   CommandOutcome::inferred). The other commands are harmless to repeat (DISARM from disarmed
//   and LAND while descending are accepted again; EXPECT_CATCH restarts its window).
// - timed_out means no ack came back after command_attempts sends: the outcome is UNKNOWN (the
//   vehicle may have executed it with every ack lost). Look at status(node).mode.
//
// Clocks: the vehicle stamps TIMESYNC replies and IMPACT frames with its free-running uint32
// microsecond clock. The link unwraps it near the latest VEHICLE_HEARTBEAT (its uptime) and
// estimates ground_time = vehicle_time + clock_offset_s from TIMESYNC exchanges, NTP style: the
// offset of the recent exchange with the shortest round trip (its error is at most half that
// round trip, less with symmetric radio delays). A vehicle clock that jumps (a reboot) restarts
// the estimate. The ground clock goes out as wrapping uint32 microseconds in TIMESYNC_REQUEST and
// milliseconds in GS_HEARTBEAT (the protocol's field), both derived from now_s.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "groundstation/link/frame_bus.hpp"
#include "groundstation/model/vehicle.hpp"
#include "pa/constants.hpp"
#include "pa/link_auth.hpp"
#include "pa/protocol.hpp"
#include "pa/vehicle_id.hpp"

namespace gs::link {

// A vehicle's link key, as provisioned on it (docs/security.md).
struct VehicleKey {
  pa::VehicleId vehicle{pa::proto::kGroundNode};
  pa::auth::Key key{};
};

struct GroundLinkConfig {
  // session token in GS_HEARTBEAT / COMMAND / KILL (pick it at random per run)
  std::uint16_t session = 1;
  std::vector<VehicleKey> keys;      // one per vehicle of the link
  double heartbeat_period_s = 0.02;  // GS_HEARTBEAT at 50 Hz (to each vehicle)
  double timesync_period_s = 0.1;    // TIMESYNC request per vehicle, 10 Hz
  double command_retry_s = 0.05;     // resend an unacknowledged COMMAND (and a KILL) after this
  int command_attempts = 5;          // sends of one COMMAND; then it has timed out (KILL: sends at most)
  // No VEHICLE_HEARTBEAT for this long: the vehicle is lost. The firmware's rule too (its hold
  // and ground heartbeat, docs/failsafe.md): shorter silences are a radio fading (100 ms outages,
  // two or three back to back), not a lost vehicle; a dead firmware is reported within 0.3 s.
  double vehicle_timeout_s = 0.3;
  double link_quality_window_s = 1.0;  // at most kHeartbeatHistory vehicle heartbeat periods
  double vehicle_heartbeat_period_s = pa::kVehicleHeartbeatPeriod_us / 1e6;  // the vehicle's (fw::LinkConfig)
};

enum class CommandState : std::uint8_t {
  pending,    // sent, no ack yet; retried every command_retry_s
  accepted,   // acknowledged as executed
  refused,    // acknowledged as refused: CommandOutcome::reason says why
  timed_out,  // no ack after command_attempts sends: outcome unknown (see the header comment)
  unknown,    // not a handle of this link, or so old that its record has been reused
};

struct CommandHandle {
  pa::VehicleId vehicle{pa::proto::kGroundNode};  // none until sent
  std::uint8_t sequence = 0;                      // the COMMAND's 8-bit sequence, per vehicle
  std::uint32_t serial = 0;  // unique per link (from 1), so a wrapped sequence is not mistaken
};

struct CommandOutcome {
  CommandState state = CommandState::unknown;
  pa::proto::CommandCode code = pa::proto::CommandCode::arm;
  pa::proto::RefuseReason reason = pa::proto::RefuseReason::none;  // from the ack
  pa::proto::Mode mode = pa::proto::Mode::disarmed;                // the vehicle's mode in the ack
  int attempts = 0;                                                // COMMAND frames sent so far
  bool inferred = false;  // accepted because a retry found the earlier attempt's effect in place
};

// A value the vehicle reported, with the ground time it was received.
template <class T>
struct Received {
  bool valid = false;
  double t_s = 0.0;
  T value{};
};

// What the ground knows of one vehicle. Heartbeat fields are those of the latest
// VEHICLE_HEARTBEAT (defaults before the first).
struct VehicleLinkStatus {
  pa::VehicleId vehicle{pa::proto::kGroundNode};
  bool heard = false;         // a VEHICLE_HEARTBEAT has arrived since construction
  bool lost = true;           // none for vehicle_timeout_s (or never heard)
  double last_heard_s = 0.0;  // ground time of the latest heartbeat
  pa::proto::Mode mode = pa::proto::Mode::disarmed;
  bool armed = false;      // kFlagArmed: the motors are enabled
  std::uint8_t flags = 0;  // pa::proto::kFlag* bits
  pa::proto::FailsafeReason failsafe = pa::proto::FailsafeReason::none;
  std::uint8_t last_setpoint_seq = 0;  // the latest setpoint sequence the vehicle accepted
  std::uint8_t vehicle_rx_errors = 0;  // frames the vehicle rejected (saturating)
  std::uint32_t uptime_ms = 0;
  // Heartbeats received / expected (one per vehicle_heartbeat_period_s) over the last
  // link_quality_window_s, 0..1; updated by tick() and by each heartbeat.
  double link_quality = 0.0;

  bool clock_synced = false;
  // ground_time = vehicle_time + offset (unwrapped vehicle clock, arbitrary epoch)
  double clock_offset_s = 0.0;
  double clock_uncertainty_s = 0.0;  // half the round trip of the exchange the offset comes from
  double round_trip_s = 0.0;         // of the latest TIMESYNC exchange
  std::uint32_t clock_resets = 0;    // times the vehicle's clock jumped (reboots) and the sync restarted

  std::uint8_t setpoint_seq_sent = 0;  // sequence of the latest RATE_THRUST sent to it
  std::uint64_t frames_received = 0;   // valid frames from this vehicle
  std::uint64_t heartbeats_received = 0;

  // The latest telemetry.
  Received<pa::proto::TelemetryRates> rates;
  Received<pa::proto::TelemetryAttitude> attitude;
  Received<pa::proto::TelemetryMotors> motors;
  Received<pa::proto::TelemetryStatus> vehicle_status;
};

struct ImpactReport {
  pa::VehicleId vehicle{pa::proto::kGroundNode};
  double t_s = 0.0;                // impact onset on the GROUND clock (via TIMESYNC) ...
  bool t_from_clock_sync = false;  // ... or, false: the ground time the frame arrived (no sync yet)
  double received_s = 0.0;         // ground time the frame arrived
  float peak_mps2 = 0.0f;
  pa::proto::ImpactClass classification = pa::proto::ImpactClass::unexpected_impact;
  bool final = false;      // false: the report on detection (provisional class); true: the event is over
  std::uint8_t count = 0;  // the vehicle's impact number; both reports of one impact share it
};

struct GroundLinkCounters {
  std::uint64_t frames_sent = 0;      // accepted by the bus
  std::uint64_t send_refused = 0;     // refused by the bus
  std::uint64_t frames_received = 0;  // every frame handed to on_frame()
  std::uint64_t accepted = 0;         // decoded, from one of our vehicles, and used
  std::uint64_t unknown_type = 0;     // undecodable, by pa::proto::DecodeStatus
  std::uint64_t wrong_length = 0;
  std::uint64_t out_of_range = 0;
  std::uint64_t foreign_node = 0;     // a vehicle-to-ground frame from a node this link does not talk to
  std::uint64_t wrong_direction = 0;  // ground-to-vehicle or HIL frames (another ground station, a plant)
  // Valid but of no use: a repeated or old heartbeat, an ack or TIMESYNC reply matching nothing outstanding.
  std::uint64_t stale = 0;
  std::uint64_t impacts_dropped = 0;   // the impact queue was full: the oldest went
  std::uint64_t commands_evicted = 0;  // too many pending commands for one vehicle: the oldest timed out
  std::uint64_t unsigned_dropped = 0;  // not sent: no session with the vehicle yet (no LINK_SESSION heard)
  std::uint64_t sessions_started = 0;  // LINK_SESSIONs that (re)started signing for a vehicle

  std::uint64_t undecodable() const { return unknown_type + wrong_length + out_of_range; }
};

class GroundLink {
 public:
  static constexpr std::size_t kCommandRecords = 16;      // per vehicle: the latest commands' outcomes
  static constexpr std::size_t kMaxPendingCommands = 8;   // per vehicle (the vehicle queues 4)
  static constexpr std::size_t kTimesyncOutstanding = 8;  // per vehicle: requests awaiting a reply
  static constexpr std::size_t kTimesyncSamples = 8;      // per vehicle: recent exchanges for the offset
  static constexpr std::size_t kHeartbeatHistory = 256;   // per vehicle: arrival times for link_quality
  static constexpr std::size_t kImpactQueue = 64;

  // `vehicles`: the vehicles (nodes 1..14, distinct, at least one) this link talks to, each with
  // its key in config.keys. Throws std::invalid_argument for a bad list, a missing or
  // unprovisioned key, or a bad configuration.
  GroundLink(FrameBus& bus, std::vector<pa::VehicleId> vehicles, const GroundLinkConfig& config = {});

  // Decode one frame read from the ground bus at ground time now_s. Returns the message when the
  // link used it (valid, from one of its vehicles, not stale), so that whoever routes it further
  // (the runtime's rates to the motors' identification) does not decode it again.
  std::optional<pa::proto::Message> on_frame(const pa::proto::Frame& frame, double now_s);
  // The periodic work: GS_HEARTBEAT when due (the first on the first call), TIMESYNC requests
  // when due (to each vehicle once it has been heard), COMMAND retries and time-outs, KILL
  // repeats, lost detection, link quality.
  void tick(double now_s);

  // One RATE_THRUST frame with the vehicle's next 4-bit sequence. Returns the input as the
  // frame carries it (quantised: 2 mrad/s, 0.01 m/s^2; thrust clamped to 0..40.95 m/s^2, rates
  // to +-65.534 rad/s), which is what the vehicle will fly and what the estimator must be told.
  // Throws std::out_of_range for an unknown node, std::invalid_argument for a non-finite input
  // (nothing is sent: the vehicle's stream goes stale and it hovers level on its own).
  gs::model::VehicleInput send_setpoint(pa::VehicleId vehicle, const gs::model::VehicleInput& input);

  // Send a COMMAND now (argument: EXPECT_CATCH's window in ms, 1..10000; 0 otherwise); tick()
  // resends it until acknowledged. A DISARM also stops the KILL repeats to that vehicle.
  // Throws std::out_of_range for an unknown node.
  CommandHandle send_command(pa::VehicleId vehicle, pa::proto::CommandCode code, std::int32_t argument,
                             double now_s);
  CommandState command_state(const CommandHandle& handle) const { return command_outcome(handle).state; }
  CommandOutcome command_outcome(const CommandHandle& handle) const;

  // KILL (motors off at once, latched until DISARM) to one vehicle, or to each vehicle of this
  // link. Never gated. Sent now, then repeated by tick() every command_retry_s, at most
  // command_attempts sends in all, until a heartbeat received after the KILL reports the
  // vehicle killed. send_kill throws std::out_of_range for a vehicle that is not ours.
  void send_kill(pa::VehicleId vehicle, pa::proto::KillReason reason);
  void send_kill_all(pa::proto::KillReason reason);

  // The ground state sent in GS_HEARTBEAT (idle until set).
  void set_ground_state(pa::proto::GroundState state) { ground_state_ = state; }

  // std::out_of_range for a vehicle that is not ours.
  const VehicleLinkStatus& status(pa::VehicleId vehicle) const;
  const std::vector<pa::VehicleId>& vehicles() const { return ids_; }

  // The IMPACT reports since the last call, oldest first (at most kImpactQueue; older ones were
  // dropped and counted).
  std::vector<ImpactReport> take_impacts();

  // A vehicle clock reading -> ground time, unwrapped near the latest heartbeat's uptime (good
  // within about 35 minutes of it). NaN while the vehicle's clock is not synced.
  // std::out_of_range for a vehicle that is not ours.
  double ground_time(pa::VehicleId vehicle, std::uint32_t vehicle_time_us) const;

  const GroundLinkCounters& counters() const { return counters_; }
  const GroundLinkConfig& config() const { return config_; }

  // The ground clock on the wire: microseconds (TIMESYNC) and milliseconds (GS_HEARTBEAT),
  // wrapping uint32.
  static std::uint32_t ground_time_us(double now_s);
  static std::uint32_t ground_time_ms(double now_s);

 private:
  struct CommandRecord {
    std::uint32_t serial = 0;  // 0: free
    pa::proto::Frame frame{};
    std::uint8_t sequence = 0;
    CommandOutcome outcome{};
    double next_send_s = 0.0;  // while pending: the next resend (or the time-out after the last)
  };
  struct OutstandingRequest {
    bool outstanding = false;
    std::uint32_t ground_time_us = 0;
    double sent_s = 0.0;
  };
  struct TimesyncSample {
    double offset_s = 0.0;
    double round_trip_s = 0.0;
  };
  struct KillRepeat {
    bool active = false;
    pa::proto::Frame frame{};
    int sends_left = 0;
    bool next_set = false;  // send_kill has no clock: the first tick() after it schedules the repeat
    double next_s = 0.0;
  };
  struct Vehicle {
    VehicleLinkStatus status;
    // The vehicle clock unwrapped to 64 bits (arbitrary epoch), at the latest heartbeat.
    std::int64_t clock_us = 0;
    std::uint8_t setpoint_seq = 0;
    std::uint8_t command_seq = 0;
    std::array<CommandRecord, kCommandRecords> commands{};
    bool timesync_started = false;
    double next_timesync_s = 0.0;
    std::uint8_t timesync_seq = 0;
    std::array<OutstandingRequest, kTimesyncOutstanding> requests{};
    std::size_t next_request_slot = 0;
    std::array<TimesyncSample, kTimesyncSamples> samples{};
    std::size_t sample_count = 0;
    std::size_t next_sample_slot = 0;
    std::array<double, kHeartbeatHistory> heartbeat_times{};
    std::size_t heartbeat_count = 0;
    std::size_t next_heartbeat_slot = 0;
    KillRepeat kill;
    std::uint64_t heartbeats_at_kill = 0;  // status.heartbeats_received when the KILL was sent
    pa::auth::Signer signer{pa::auth::Key{}};
  };

  int index_of(std::uint8_t node) const;  // -1: not one of ours
  Vehicle& vehicle(pa::VehicleId id);     // std::out_of_range when not ours
  const Vehicle& vehicle(pa::VehicleId id) const;
  // The frame, then its AUTH; false (counted) when the bus refused either or there is no session.
  bool send(Vehicle& v, const pa::proto::Frame& frame);
  void on_link_session(Vehicle& v, const pa::proto::LinkSession& session);
  // Each answers whether the frame was news (false: counted stale).
  bool on_heartbeat(Vehicle& v, const pa::proto::VehicleHeartbeat& hb, double now_s);
  bool on_timesync_reply(Vehicle& v, const pa::proto::TimesyncReply& reply, double now_s);
  bool on_ack(Vehicle& v, const pa::proto::CommandAck& ack);
  void on_impact(Vehicle& v, const pa::proto::Impact& impact, double now_s);
  void reset_clock(Vehicle& v);
  void update_link_quality(Vehicle& v, double now_s) const;
  // True when periodic work is due at now_s, and schedules its next time.
  static bool due(bool& started, double& next_s, double period_s, double now_s);
  void tick_commands(Vehicle& v, double now_s);
  void tick_kill(Vehicle& v, double now_s);
  static bool kill_confirmed(const Vehicle& v, std::uint64_t heartbeats_at_kill);
  std::int64_t unwrap_vehicle_time(const Vehicle& v, std::uint32_t vehicle_time_us) const;

  FrameBus& bus_;
  std::vector<pa::VehicleId> ids_;
  GroundLinkConfig config_;
  std::array<std::int8_t, 16> index_{};  // node -> vehicles_ index, -1: not ours
  std::vector<Vehicle> vehicles_;        // sized once, in the constructor

  pa::proto::GroundState ground_state_ = pa::proto::GroundState::idle;
  bool heartbeat_started_ = false;
  double next_heartbeat_s_ = 0.0;
  std::uint8_t heartbeat_seq_ = 0;
  std::uint32_t command_serial_ = 0;

  std::array<ImpactReport, kImpactQueue> impacts_{};
  std::size_t impact_head_ = 0;
  std::size_t impact_count_ = 0;

  GroundLinkCounters counters_;
};

}  // namespace gs::link
