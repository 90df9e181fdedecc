#include "groundstation/service/process.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string_view>
#include <utility>

#include "groundstation/dds/event_detail.hpp"
#include "groundstation/dds/mocap_conversion.hpp"
#include "groundstation/dds/telemetry_conversion.hpp"

namespace gs::service {
namespace {

using mission::Reason;

struct CommandName {
  std::uint8_t kind;
  const char* name;
};
constexpr CommandName kCommandNames[] = {
    {dds::command_kind::kTakeOff, "take-off"}, {dds::command_kind::kThrow, "throw"},
    {dds::command_kind::kAbort, "abort"},      {dds::command_kind::kLand, "land"},
    {dds::command_kind::kKill, "kill"},
};

std::string str(std::string_view s) { return std::string(s); }

// A mission's reasons that end a throw or a catch early.
bool is_abort(Reason reason) {
  return reason == Reason::abort_requested || reason == Reason::out_of_reach ||
         reason == Reason::infeasible || reason == Reason::pole_left_early;
}
// The catcher's, that call the catch off without a task change of the catch's own.
bool is_lost(Reason reason) { return reason == Reason::vehicle_lost || reason == Reason::estimate_lost; }

}  // namespace

std::string command_name(std::uint8_t kind) {
  for (const CommandName& c : kCommandNames)
    if (c.kind == kind) return c.name;
  return "unknown command " + std::to_string(static_cast<int>(kind));
}

std::optional<std::uint8_t> command_from_name(const std::string& name) {
  for (const CommandName& c : kCommandNames)
    if (name == c.name) return c.kind;
  return std::nullopt;
}

std::string answer_prefix(std::uint32_t sequence_number) {
  return "command " + std::to_string(sequence_number) + ":";
}

Process::Process(link::FrameBus& bus, const dds::Participant& participant,
                 const runtime::GroundStationConfig& config, const ProcessConfig& process)
    : station_(bus, config),
      config_(process),
      mocap_(participant),
      commands_(participant),
      vehicle_telemetry_{dds::Writer<dds::VehicleTelemetry>(
                             participant, dds::vehicle_telemetry_topic(pa::kVehicle1).c_str()),
                         dds::Writer<dds::VehicleTelemetry>(
                             participant, dds::vehicle_telemetry_topic(pa::kVehicle2).c_str())},
      pole_telemetry_(participant),
      events_(participant),
      vehicle_poses_{
          dds::Writer<dds::PoseStamped>(participant, dds::vehicle_pose_topic(pa::kVehicle1).c_str()),
          dds::Writer<dds::PoseStamped>(participant, dds::vehicle_pose_topic(pa::kVehicle2).c_str())},
      pole_pose_(participant, dds::kPolePoseTopic) {}

void Process::on_frame(const pa::proto::Frame& frame, double now_s) {
  ++counters_.can_frames;
  station_.on_frame(frame, now_s);
}

void Process::step(double now_s) {
  // Commands first: a KILL must not wait behind an estimator update.
  take_commands(now_s);
  take_mocap(now_s);
  station_.tick(now_s);
  if (!next_telemetry_s_ || now_s >= *next_telemetry_s_) {
    publish_telemetry(now_s);
    // Fixed rate; after a stall it starts again from now rather than catching up in a burst.
    next_telemetry_s_ = next_telemetry_s_ && now_s - *next_telemetry_s_ < config_.telemetry_period_s
                            ? *next_telemetry_s_ + config_.telemetry_period_s
                            : now_s + config_.telemetry_period_s;
  }
  publish_changes(now_s);
}

void Process::take_commands(double now_s) {
  // The topic keeps up to 16: KILLs among them are acted on before the rest.
  std::array<dds::OperatorCommand, 16> taken{};
  std::size_t count = 0;
  while (count < taken.size()) {
    const dds::OperatorCommand* c = commands_.take();
    if (c == nullptr) break;
    taken[count++] = *c;
  }
  for (std::size_t i = 0; i < count; ++i)
    if (taken[i].kind == dds::command_kind::kKill) act_on(taken[i], now_s);
  for (std::size_t i = 0; i < count; ++i)
    if (taken[i].kind != dds::command_kind::kKill) act_on(taken[i], now_s);
}

bool Process::seen_before(std::uint32_t sequence_number) {
  for (std::size_t i = 0; i < recent_count_; ++i)
    if (recent_[i] == sequence_number) return true;
  recent_[recent_next_] = sequence_number;
  recent_next_ = (recent_next_ + 1) % recent_.size();
  if (recent_count_ < recent_.size()) ++recent_count_;
  return false;
}

void Process::act_on(const dds::OperatorCommand& command, double now_s) {
  if (!dds::is_command_kind(command.kind)) {
    answer(command, false, "command kind " + std::to_string(command.kind) + " refused: unknown", now_s);
    return;
  }
  const std::string name = command_name(command.kind);
  const bool all = command.target == 0;
  const pa::VehicleId target(command.target);
  if (!all && !pa::is_act_vehicle(target)) {
    answer(command, false, name + " refused: no vehicle " + std::to_string(command.target) + " in the act",
           now_s);
    return;
  }
  if (command.kind == dds::command_kind::kKill) {
    seen_before(command.sequence_number);
    station_.request_kill(all ? std::nullopt : std::optional<pa::VehicleId>(target),
                          pa::proto::KillReason::operator_request);
    ++counters_.kills;
    answer(command, true,
           all ? "kill sent to every vehicle" : "kill sent to vehicle " + std::to_string(command.target),
           now_s);
    return;
  }
  if (seen_before(command.sequence_number)) {
    answer(command, false, name + " refused: this sequence number was acted on already", now_s);
    return;
  }
  switch (command.kind) {
    case dds::command_kind::kTakeOff:
    case dds::command_kind::kLand:
    case dds::command_kind::kAbort:
      if (!all) {
        answer(command, false, name + " refused: it acts on both vehicles (target 0)", now_s);
        return;
      }
      if (command.kind == dds::command_kind::kTakeOff) station_.request_take_off();
      if (command.kind == dds::command_kind::kLand) station_.request_land();
      if (command.kind == dds::command_kind::kAbort) station_.request_abort();
      answer(command, true, name + " requested", now_s);
      return;
    case dds::command_kind::kThrow: {
      runtime::AttemptRequest request;
      if (!all) request.thrower = target;
      if (!station_.request_attempt(request)) {
        answer(command, false, "throw refused: " + station_.refusal(), now_s);
        return;
      }
      thrower_ = request.thrower;
      const int number = station_.current_attempt().number;
      answer(command, true,
             "throw: attempt " + std::to_string(number) + " with vehicle " +
                 std::to_string(request.thrower.node()) + " throwing",
             now_s);
      publish(dds::event_kind::kAttempt, request.thrower,
              dds::attempt_event_detail(number, station_.throw_frame(request.thrower).origin_m), now_s);
      return;
    }
    default: answer(command, false, name + " refused: unknown kind", now_s); return;
  }
}

void Process::answer(const dds::OperatorCommand& command, bool accepted, const std::string& detail,
                     double now_s) {
  ++(accepted ? counters_.commands_accepted : counters_.commands_refused);
  const pa::VehicleId target(command.target);
  publish(accepted ? dds::event_kind::kCommandAccepted : dds::event_kind::kCommandRefused,
          pa::is_act_vehicle(target) ? std::optional<pa::VehicleId>(target) : std::nullopt,
          answer_prefix(command.sequence_number) + " " + detail, now_s);
}

void Process::take_mocap(double now_s) {
  // The reader keeps the newest frame only: at most one is waiting.
  while (const dds::NamedPoseArray* m = mocap_.take()) on_mocap(*m, now_s);
}

bool Process::await_mocap(std::uint64_t frames, double now_s, std::chrono::nanoseconds timeout) {
  // Frames are counted, and the stamps (the plant's time there) say more: the plant publishes a
  // frame in the first step at or after its delivery, and one writer's frames arrive in order.
  // So once a frame stamped within this clock's step or later has been taken, every frame this
  // clock counts is in, and the count is set right: the clock's, plus the frames taken that were
  // published after it. That keeps the count true through a restart or a release by the plant,
  // when frames from after a stale clock are waiting and others were never delivered.
  constexpr double kSlack_s = 1e-6;  // stamps and clock times are both plant time, rounded
  const double step_start_s = now_s - config_.mocap.clock_step_s + kSlack_s;
  std::uint64_t newer = 0;
  const auto end = std::chrono::steady_clock::now() + timeout;
  for (;;) {
    if (last_stamp_s_ && *last_stamp_s_ > step_start_s) {
      mocap_counted_ = frames + newer;
      return true;
    }
    if (mocap_counted_ >= frames) return true;
    const auto left = end - std::chrono::steady_clock::now();
    if (left <= std::chrono::nanoseconds::zero()) {
      mocap_counted_ = frames + newer;
      return false;
    }
    const dds::NamedPoseArray* m = mocap_.wait_take(left);
    if (m == nullptr) continue;
    on_mocap(*m, now_s);
    if (*last_stamp_s_ > now_s + kSlack_s) ++newer;
  }
}

void Process::on_mocap(const dds::NamedPoseArray& message, double now_s) {
  dds::MocapFrameIn in = dds::mocap_frame_from_dds(message, config_.mocap.names);
  counters_.mocap_unknown_bodies += in.unknown_bodies;
  counters_.mocap_invalid_poses += in.invalid_poses;
  counters_.mocap_duplicate_bodies += in.duplicate_bodies;
  counters_.mocap_excess_poses += in.excess_poses;
  if (first_unknown_body_.empty() && !in.first_unknown.empty()) first_unknown_body_ = in.first_unknown;
  ++counters_.mocap_frames;
  ++mocap_counted_;
  // The stamp on the ground clock, and how long the frame took from the node to here.
  const double stamp_s = dds::to_seconds(in.stamp_ns - stamp_offset_ns_);
  last_stamp_s_ = stamp_s;
  const double delay_s = now_s - stamp_s;
  if (std::isfinite(delay_s) && delay_s >= -config_.mocap.max_stamp_lead_s &&
      delay_s <= config_.mocap.max_stamp_age_s) {
    counters_.mocap_delay_sum_s += delay_s;
    counters_.mocap_delay_max_s = std::max(counters_.mocap_delay_max_s, delay_s);
    in.frame.t_s = stamp_s - config_.mocap.latency_s;
  } else {
    ++counters_.mocap_implausible_stamps;
    in.frame.t_s = now_s - config_.mocap.latency_s;
  }
  station_.on_mocap(in.frame, now_s);
}

std::int64_t Process::ros_time_ns(double now_s) const {
  return dds::to_nanoseconds(now_s) + stamp_offset_ns_;
}

void Process::publish_telemetry(double now_s) {
  const estimation::StateEstimator& estimator = station_.estimator();
  const std::int64_t stamp_ns = ros_time_ns(now_s);
  for (const pa::VehicleId v : pa::kActVehicles) {
    std::optional<estimation::VehicleEstimate> estimate;
    if (estimator.vehicle_initialised(v)) estimate = estimator.vehicle(v);
    vehicle_telemetry_[pa::act_slot(v)].write(
        dds::vehicle_telemetry_to_ros(v, stamp_ns, station_.link().status(v), station_.task(v), estimate));
    ++counters_.telemetry_published;
  }
  std::optional<dds::CatchForecast> forecast;
  const runtime::AttemptReport& attempt = station_.current_attempt();
  if (station_.attempt_phase() == runtime::AttemptPhase::flight && attempt.predicted && attempt.launch_s) {
    dds::CatchForecast f;
    f.stamp_ns = ros_time_ns(*attempt.launch_s + attempt.predicted->t_s);
    f.point_m =
        Eigen::Vector3d(attempt.predicted->xy_m.x(), attempt.predicted->xy_m.y(), station_.catch_height());
    f.catcher = pa::other_vehicle(thrower_);
    forecast = f;
  }
  pole_telemetry_.write(dds::pole_telemetry_to_ros(estimator.pole(), stamp_ns, forecast));
  ++counters_.telemetry_published;
  // The same estimates as ROS 2 poses.
  for (const pa::VehicleId v : pa::kActVehicles) {
    if (!estimator.vehicle_initialised(v)) continue;
    vehicle_poses_[pa::act_slot(v)].write(dds::vehicle_pose_to_ros(estimator.vehicle(v), stamp_ns));
    ++counters_.ros_poses_published;
  }
  if (const estimation::PoleEstimate pole = estimator.pole(); pole.valid) {
    pole_pose_.write(dds::pole_pose_to_ros(pole.state, stamp_ns));
    ++counters_.ros_poses_published;
  }
}

void Process::publish_changes(double now_s) {
  for (const runtime::MissionEvent& e : station_.take_events()) {
    publish(dds::event_kind::kTaskChange, e.vehicle, dds::task_change_detail(e.from, e.to, e.reason, e.why),
            now_s);
    if (is_abort(e.reason))
      publish(dds::event_kind::kAbort, e.vehicle, str(mission::reason_name(e.reason)), now_s);
    if (e.to == mission::Task::failsafe && e.from != mission::Task::failsafe)
      publish(dds::event_kind::kFailsafe, e.vehicle,
              "mission failsafe (" + str(mission::reason_name(e.reason)) + ")", now_s);
  }
  for (const pa::VehicleId v : pa::kActVehicles) {
    const bool waiting = station_.waiting_for_pole(v);
    if (waiting == std::exchange(waiting_for_pole_[pa::act_slot(v)], waiting)) continue;
    publish(dds::event_kind::kPoleWanted, v, dds::pole_wanted_detail(waiting), now_s);
  }
  for (const link::ImpactReport& i : station_.take_impacts()) {
    if (!i.final) continue;  // the final report of each impact, with its settled class
    char detail[96];
    std::snprintf(detail, sizeof detail, "class %d, peak %.1f m/s^2", static_cast<int>(i.classification),
                  static_cast<double>(i.peak_mps2));
    publish(dds::event_kind::kImpact, i.vehicle, detail, now_s);
  }
  const runtime::AttemptReport& current = station_.current_attempt();
  if (current.launch_s && current.number != launch_published_) {
    launch_published_ = current.number;
    publish(dds::event_kind::kLaunch, std::nullopt, "attempt " + std::to_string(current.number), now_s);
  }
  const std::vector<runtime::AttemptReport>& done = station_.attempts();
  for (; attempts_published_ < done.size(); ++attempts_published_) {
    const runtime::AttemptReport& r = done[attempts_published_];
    std::string detail = "attempt " + std::to_string(r.number) + ": catcher " +
                         str(mission::reason_name(r.catcher_end)) + ", thrower " +
                         str(mission::reason_name(r.thrower_end));
    if (r.catcher_at_impact_m) {
      char at[80];
      std::snprintf(at, sizeof at, ", catcher at impact (%.3f, %.3f, %.3f) m", r.catcher_at_impact_m->x(),
                    r.catcher_at_impact_m->y(), r.catcher_at_impact_m->z());
      detail += at;
    }
    if (!r.caught && is_lost(r.catcher_end))
      publish(dds::event_kind::kAbort, pa::other_vehicle(thrower_),
              "catch aborted: the catcher is " + str(mission::reason_name(r.catcher_end)), now_s);
    if (r.end == runtime::AttemptEnd::motors_unidentified)
      publish(dds::event_kind::kAbort, std::nullopt,
              "attempt ended before the throw: a vehicle's motors could not be identified", now_s);
    publish(r.caught ? dds::event_kind::kCatchSuccess : dds::event_kind::kCatchMiss, std::nullopt, detail,
            now_s);
  }
  for (const pa::VehicleId v : pa::kActVehicles) {
    const link::VehicleLinkStatus& s = station_.link().status(v);
    VehicleSeen& seen = seen_[pa::act_slot(v)];
    if (s.heard && s.lost && !seen.lost) publish(dds::event_kind::kVehicleLost, v, "no heartbeat", now_s);
    if (s.heard && !s.lost && seen.lost)
      publish(dds::event_kind::kVehicleBack, v, seen.heard ? "heartbeats again" : "first heartbeat", now_s);
    if (s.failsafe != seen.failsafe && s.failsafe != pa::proto::FailsafeReason::none)
      publish(dds::event_kind::kFailsafe, v,
              "the vehicle reports failsafe reason " + std::to_string(static_cast<int>(s.failsafe)), now_s);
    seen.heard = s.heard;
    seen.lost = s.lost;
    seen.failsafe = s.failsafe;
  }
}

void Process::publish(std::uint8_t kind, std::optional<pa::VehicleId> vehicle, const std::string& detail,
                      double now_s) {
  dds::Event e{};
  e.stamp = dds::ros_time(ros_time_ns(now_s));
  e.kind = kind;
  e.vehicle = vehicle ? vehicle->node() : 0;
  // The IDL bounds the detail (a fixed array in C): a longer one is cut.
  std::snprintf(e.detail, sizeof e.detail, "%s", detail.c_str());
  events_.write(e);
  ++counters_.events_published;
}

std::string Process::summary() const {
  const link::GroundLinkCounters& l = station_.link().counters();
  const ProcessCounters& c = counters_;
  const auto u = [](std::uint64_t n) { return static_cast<unsigned long long>(n); };
  const std::uint64_t timed = c.mocap_frames - c.mocap_implausible_stamps;
  char text[1024];
  std::snprintf(text, sizeof text,
                "CAN frames received %llu, sent %llu (refused by the bus %llu, unsigned dropped %llu)\n"
                "motion-capture frames %llu on rt/poses (unknown bodies %llu, invalid poses %llu, duplicate "
                "bodies %llu, poses beyond %zu %llu)\n"
                "motion-capture stamp to arrival: mean %.2f ms, max %.2f ms over %llu frames; implausible "
                "stamps %llu\n"
                "operator commands accepted %llu, refused %llu, kills %llu\n"
                "attempts completed %zu, telemetry samples %llu (ROS 2 poses %llu), events %llu\n",
                u(c.can_frames), u(l.frames_sent), u(l.send_refused), u(l.unsigned_dropped),
                u(c.mocap_frames), u(c.mocap_unknown_bodies), u(c.mocap_invalid_poses),
                u(c.mocap_duplicate_bodies), dds::kMaxPoses, u(c.mocap_excess_poses),
                timed > 0 ? 1e3 * c.mocap_delay_sum_s / static_cast<double>(timed) : 0.0,
                1e3 * c.mocap_delay_max_s, u(timed), u(c.mocap_implausible_stamps), u(c.commands_accepted),
                u(c.commands_refused), u(c.kills), station_.attempts().size(), u(c.telemetry_published),
                u(c.ros_poses_published), u(c.events_published));
  std::string out = text;
  if (!first_unknown_body_.empty())
    out += "motion capture: body '" + first_unknown_body_ + "' is none of vehicle 1 ('" +
           config_.mocap.names.vehicle1 + "'), vehicle 2 ('" + config_.mocap.names.vehicle2 +
           "') or the pole ('" + config_.mocap.names.pole +
           "'): ignored (--mocap-vehicle1, --mocap-vehicle2, --mocap-pole)\n";
  if (station_.volume_breaches() > 0)
    out += "arena volume: a flying vehicle was found outside it " +
           std::to_string(station_.volume_breaches()) + " times and sent to land\n";
  if (c.mocap_implausible_stamps > 0)
    out +=
        "motion capture: stamps the clocks cannot explain (in the future or older than the limit): are the "
        "motion-capture host's and this host's clocks synchronised? Those frames were timed by arrival\n";
  // The leg from the ground station to each vehicle and back: TIMESYNC's round trip (the radio
  // both ways and up to a tick on board), half of which bounds the clock offset's error.
  for (const pa::VehicleId v : pa::kActVehicles) {
    const link::VehicleLinkStatus& s = station_.link().status(v);
    char line[256];
    if (!s.heard)
      std::snprintf(line, sizeof line, "vehicle %u: never heard\n", static_cast<unsigned>(v.node()));
    else if (!s.clock_synced)
      std::snprintf(line, sizeof line, "vehicle %u: link quality %.2f, no TIMESYNC answered\n",
                    static_cast<unsigned>(v.node()), s.link_quality);
    else
      std::snprintf(line, sizeof line,
                    "vehicle %u: link quality %.2f, TIMESYNC round trip %.1f ms (latest), clock offset known "
                    "within %.1f ms\n",
                    static_cast<unsigned>(v.node()), s.link_quality, 1e3 * s.round_trip_s,
                    1e3 * s.clock_uncertainty_s);
    out += line;
  }
  return out;
}

}  // namespace gs::service
