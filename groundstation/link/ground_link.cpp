#include "groundstation/link/ground_link.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <stdexcept>
#include <string>

#include <sodium.h>

#include "pa/sequence.hpp"

namespace gs::link {

using namespace pa::proto;

namespace {

// The MAC from libsodium (SipHash-2-4, 64-bit output, little-endian): the vehicle computes the
// same with pa::auth::siphash24, which tests/shared/link_auth_test checks against this.
std::uint64_t sodium_siphash24(const pa::auth::Key& key, const std::uint8_t* message, std::size_t length) {
  unsigned char out[crypto_shorthash_siphash24_BYTES];
  crypto_shorthash_siphash24(out, message, length, key.data());
  std::uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v |= static_cast<std::uint64_t>(out[i]) << (8 * i);
  return v;
}

// A heartbeat whose vehicle clock advanced by more than this beyond (or behind) the ground time
// since the previous one means the vehicle's clock jumped: it rebooted. Radio jitter is a few
// ms and crystal drift 0.1 ms/s, so this never fires on a running vehicle.
constexpr double kClockJump_s = 0.5;
// Setpoints are converted to float for the frame; anything beyond this saturates in encode()
// anyway, and clamping first keeps huge finite doubles from becoming float infinities.
constexpr double kSetpointClamp = 1.0e6;
// The caller's tick times are computed in floating point: a tick meant for the due time may land
// a rounding error before it, which must not delay the work by a whole tick.
constexpr double kScheduleSlack_s = 1e-6;

bool reached(double now_s, double due_s) { return now_s >= due_s - kScheduleSlack_s; }

bool positive_finite(double v) { return std::isfinite(v) && v > 0.0; }

void require_finite(double now_s, const char* what) {
  if (!std::isfinite(now_s))
    throw std::invalid_argument(std::string("GroundLink::") + what + ": now_s is not finite");
}

float to_frame_value(double v) { return static_cast<float>(std::clamp(v, -kSetpointClamp, kSetpointClamp)); }

}  // namespace

std::uint32_t GroundLink::ground_time_us(double now_s) {
  // Modulo 2^32 through the unsigned 64-bit conversion, negative times included.
  return static_cast<std::uint32_t>(static_cast<std::uint64_t>(std::llround(now_s * 1e6)));
}

std::uint32_t GroundLink::ground_time_ms(double now_s) {
  return static_cast<std::uint32_t>(
      static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(now_s * 1e3))));
}

GroundLink::GroundLink(FrameBus& bus, std::vector<pa::VehicleId> vehicles, const GroundLinkConfig& config)
    : bus_(bus), ids_(std::move(vehicles)), config_(config) {
  if (ids_.empty()) throw std::invalid_argument("GroundLink: no vehicles");
  index_.fill(-1);
  for (std::size_t i = 0; i < ids_.size(); ++i) {
    const std::uint8_t n = ids_[i].node();
    if (!ids_[i].valid())
      throw std::invalid_argument("GroundLink: vehicle node " + std::to_string(n) + " is not 1..14");
    if (index_[n] >= 0)
      throw std::invalid_argument("GroundLink: vehicle node " + std::to_string(n) + " is listed twice");
    index_[n] = static_cast<std::int8_t>(i);
  }
  if (!positive_finite(config_.heartbeat_period_s) || !positive_finite(config_.timesync_period_s) ||
      !positive_finite(config_.command_retry_s) || !positive_finite(config_.vehicle_timeout_s) ||
      !positive_finite(config_.link_quality_window_s) || !positive_finite(config_.vehicle_heartbeat_period_s))
    throw std::invalid_argument("GroundLink: periods and time-outs must be positive and finite");
  if (config_.command_attempts < 1)
    throw std::invalid_argument("GroundLink: command_attempts must be at least 1");
  if (config_.link_quality_window_s / config_.vehicle_heartbeat_period_s >
      static_cast<double>(kHeartbeatHistory))
    throw std::invalid_argument("GroundLink: link_quality_window_s spans more heartbeats than are kept");

  if (sodium_init() < 0) throw std::runtime_error("GroundLink: libsodium failed to initialise");
  vehicles_.resize(ids_.size());
  for (std::size_t i = 0; i < ids_.size(); ++i) {
    vehicles_[i].status.vehicle = ids_[i];
    const auto key = std::find_if(config_.keys.begin(), config_.keys.end(),
                                  [&](const VehicleKey& k) { return k.vehicle == ids_[i]; });
    if (key == config_.keys.end() || !pa::auth::provisioned(key->key))
      throw std::invalid_argument("GroundLink: no key for vehicle " + std::to_string(ids_[i].node()));
    vehicles_[i].signer = pa::auth::Signer(key->key, sodium_siphash24);
  }
}

int GroundLink::index_of(std::uint8_t node) const { return node < index_.size() ? index_[node] : -1; }

const GroundLink::Vehicle& GroundLink::vehicle(pa::VehicleId id) const {
  const int i = index_of(id.node());
  if (i < 0)
    throw std::out_of_range("GroundLink: node " + std::to_string(id.node()) + " is not one of its vehicles");
  return vehicles_[static_cast<std::size_t>(i)];
}

GroundLink::Vehicle& GroundLink::vehicle(pa::VehicleId id) {
  return const_cast<Vehicle&>(static_cast<const GroundLink&>(*this).vehicle(id));
}

const VehicleLinkStatus& GroundLink::status(pa::VehicleId id) const { return vehicle(id).status; }

bool GroundLink::send(Vehicle& v, const Frame& frame) {
  Frame auth;
  if (!v.signer.sign(frame, auth)) {
    ++counters_.unsigned_dropped;
    return false;
  }
  for (const Frame* f : std::initializer_list<const Frame*>{&frame, &auth}) {
    if (!bus_.send(*f)) {
      ++counters_.send_refused;
      return false;
    }
    ++counters_.frames_sent;
  }
  return true;
}

void GroundLink::on_link_session(Vehicle& v, const LinkSession& session) {
  // A new nonce is a new boot of the vehicle; the same one with a counter at or past ours means
  // this link started after the vehicle had accepted frames (a ground-station restart).
  if (v.signer.active() && session.nonce == v.signer.nonce() &&
      session.last_counter < v.signer.next_counter())
    return;
  v.signer.start_session(session.nonce, session.last_counter);
  ++counters_.sessions_started;
}

bool GroundLink::due(bool& started, double& next_s, double period_s, double now_s) {
  if (started && !reached(now_s, next_s)) return false;
  // Keep the phase while on time; after a gap (a late tick) start again from now rather than
  // sending a burst to catch up.
  next_s = started ? next_s + period_s : now_s + period_s;
  if (reached(now_s, next_s)) next_s = now_s + period_s;
  started = true;
  return true;
}

// ---------------------------------------------------------------------------------------
// Receiving
// ---------------------------------------------------------------------------------------
std::optional<Message> GroundLink::on_frame(const Frame& frame, double now_s) {
  require_finite(now_s, "on_frame");
  ++counters_.frames_received;
  Message m;
  switch (decode(frame, m)) {
    case DecodeStatus::ok: break;
    case DecodeStatus::unknown_type: ++counters_.unknown_type; return std::nullopt;
    case DecodeStatus::wrong_length: ++counters_.wrong_length; return std::nullopt;
    case DecodeStatus::out_of_range: ++counters_.out_of_range; return std::nullopt;
  }
  // decode() succeeded, so the type is in the catalogue.
  if (find_type(static_cast<std::uint8_t>(m.type))->direction != Direction::vehicle_to_ground) {
    ++counters_.wrong_direction;
    return std::nullopt;
  }
  const int i = index_of(m.node);
  if (i < 0) {
    ++counters_.foreign_node;
    return std::nullopt;
  }
  Vehicle& v = vehicles_[static_cast<std::size_t>(i)];
  ++v.status.frames_received;

  bool used = true;
  switch (m.type) {
    case Type::vehicle_heartbeat: used = on_heartbeat(v, m.vehicle_heartbeat, now_s); break;
    case Type::timesync_reply: used = on_timesync_reply(v, m.timesync_reply, now_s); break;
    case Type::command_ack: used = on_ack(v, m.command_ack); break;
    case Type::impact: on_impact(v, m.impact, now_s); break;
    case Type::telemetry_rates: v.status.rates = {true, now_s, m.telemetry_rates}; break;
    case Type::telemetry_attitude: v.status.attitude = {true, now_s, m.telemetry_attitude}; break;
    case Type::telemetry_motors: v.status.motors = {true, now_s, m.telemetry_motors}; break;
    case Type::telemetry_status: v.status.vehicle_status = {true, now_s, m.telemetry_status}; break;
    case Type::link_session: on_link_session(v, m.link_session); break;
    default: used = false; break;  // no other vehicle-to-ground type exists
  }
  if (!used) {
    ++counters_.stale;
    return std::nullopt;
  }
  ++counters_.accepted;
  return m;
}

bool GroundLink::on_heartbeat(Vehicle& v, const VehicleHeartbeat& hb, double now_s) {
  VehicleLinkStatus& s = v.status;
  // The uptime is the vehicle's 32-bit microsecond clock in ms (it wraps with it, every 71.6
  // min), so it is unwrapped as a microsecond stamp: the clock of the IMPACT and TIMESYNC frames.
  const std::uint32_t stamp_us = hb.uptime_ms * 1000u;
  if (!s.heard) {
    v.clock_us = stamp_us;
  } else {
    const std::int64_t advance_us = pa::elapsed_us(stamp_us, static_cast<std::uint32_t>(v.clock_us));
    const double ground_advance_s = now_s - s.last_heard_s;
    if (std::abs(static_cast<double>(advance_us) * 1e-6 - ground_advance_s) > kClockJump_s) {
      reset_clock(v);
      ++s.clock_resets;
      v.clock_us = stamp_us;
    } else if (advance_us <= 0) {
      return false;  // a repeated or older heartbeat: not news
    } else {
      v.clock_us += advance_us;
    }
  }
  s.heard = true;
  s.lost = false;
  s.last_heard_s = now_s;
  s.mode = hb.mode;
  s.flags = hb.flags;
  s.armed = (hb.flags & kFlagArmed) != 0;
  s.failsafe = hb.failsafe;
  s.last_setpoint_seq = hb.last_setpoint_seq;
  s.vehicle_rx_errors = hb.rx_errors;
  s.uptime_ms = hb.uptime_ms;
  ++s.heartbeats_received;
  v.heartbeat_times[v.next_heartbeat_slot] = now_s;
  v.next_heartbeat_slot = (v.next_heartbeat_slot + 1) % kHeartbeatHistory;
  v.heartbeat_count = std::min(v.heartbeat_count + 1, kHeartbeatHistory);
  update_link_quality(v, now_s);
  return true;
}

void GroundLink::reset_clock(Vehicle& v) {
  v.sample_count = 0;
  v.next_sample_slot = 0;
  for (OutstandingRequest& r : v.requests) r.outstanding = false;  // their replies carry the old clock
  v.status.clock_synced = false;
  v.status.clock_offset_s = 0.0;
  v.status.clock_uncertainty_s = 0.0;
}

std::int64_t GroundLink::unwrap_vehicle_time(const Vehicle& v, std::uint32_t vehicle_time_us) const {
  return v.clock_us + pa::elapsed_us(vehicle_time_us, static_cast<std::uint32_t>(v.clock_us));
}

// NTP with the vehicle's receive and transmit stamps taken as one (fw::Vehicle stamps the
// request when it is read and replies on its next 1 kHz tick): the vehicle read the request
// at ground time (sent + received) / 2 when the two legs take equally long.
bool GroundLink::on_timesync_reply(Vehicle& v, const pa::proto::TimesyncReply& reply, double now_s) {
  if (!v.status.heard) return false;  // no uptime yet to unwrap the vehicle's stamp near
  OutstandingRequest* request = nullptr;
  for (OutstandingRequest& r : v.requests)
    if (r.outstanding && r.ground_time_us == reply.ground_time_us) request = &r;
  if (request == nullptr) return false;  // not ours, answered already, or from before a reset
  request->outstanding = false;
  const double round_trip_s = now_s - request->sent_s;
  if (round_trip_s < 0.0) return false;
  const double vehicle_s = static_cast<double>(unwrap_vehicle_time(v, reply.vehicle_time_us)) * 1e-6;
  v.samples[v.next_sample_slot] = TimesyncSample{0.5 * (request->sent_s + now_s) - vehicle_s, round_trip_s};
  v.next_sample_slot = (v.next_sample_slot + 1) % kTimesyncSamples;
  v.sample_count = std::min(v.sample_count + 1, kTimesyncSamples);

  // The shortest round trip bounds the error best (queueing only ever adds delay).
  const TimesyncSample* best = &v.samples[0];
  for (std::size_t i = 1; i < v.sample_count; ++i)
    if (v.samples[i].round_trip_s < best->round_trip_s) best = &v.samples[i];
  VehicleLinkStatus& s = v.status;
  s.clock_synced = true;
  s.clock_offset_s = best->offset_s;
  s.clock_uncertainty_s = 0.5 * best->round_trip_s;
  s.round_trip_s = round_trip_s;
  return true;
}

bool GroundLink::on_ack(Vehicle& v, const CommandAck& ack) {
  for (CommandRecord& r : v.commands) {
    const bool pending = r.serial != 0 && r.outcome.state == CommandState::pending;
    if (!pending || r.sequence != ack.seq || r.outcome.code != ack.code) continue;
    CommandOutcome& o = r.outcome;
    o.reason = ack.reason;
    o.mode = ack.mode;
    if (ack.result == AckResult::accepted || ack.result == AckResult::duplicate) {
      o.state = CommandState::accepted;
    } else if (o.attempts > 1 && o.code == CommandCode::arm && ack.reason == RefuseReason::not_disarmed &&
               ack.mode == Mode::armed) {
      // The vehicle executes a retried COMMAND again: an earlier attempt armed it, its ack was lost.
      o.state = CommandState::accepted;
      o.inferred = true;
    } else {
      o.state = CommandState::refused;
    }
    return true;
  }
  return false;  // a late ack of a resolved command, or not ours
}

void GroundLink::on_impact(Vehicle& v, const pa::proto::Impact& impact, double now_s) {
  ImpactReport r;
  r.vehicle = v.status.vehicle;
  r.received_s = now_s;
  r.t_from_clock_sync = v.status.clock_synced;
  r.t_s = r.t_from_clock_sync ? static_cast<double>(unwrap_vehicle_time(v, impact.vehicle_time_us)) * 1e-6 +
                                    v.status.clock_offset_s
                              : now_s;
  r.peak_mps2 = impact.peak_mps2;
  r.classification = impact.classification;
  r.final = impact.final;
  r.count = impact.count;
  if (impact_count_ == kImpactQueue) {
    impact_head_ = (impact_head_ + 1) % kImpactQueue;
    --impact_count_;
    ++counters_.impacts_dropped;
  }
  impacts_[(impact_head_ + impact_count_) % kImpactQueue] = r;
  ++impact_count_;
}

std::vector<ImpactReport> GroundLink::take_impacts() {
  std::vector<ImpactReport> out;
  out.reserve(impact_count_);
  for (std::size_t i = 0; i < impact_count_; ++i) out.push_back(impacts_[(impact_head_ + i) % kImpactQueue]);
  impact_head_ = 0;
  impact_count_ = 0;
  return out;
}

double GroundLink::ground_time(pa::VehicleId id, std::uint32_t vehicle_time_us) const {
  const Vehicle& v = vehicle(id);
  if (!v.status.clock_synced) return std::numeric_limits<double>::quiet_NaN();
  return static_cast<double>(unwrap_vehicle_time(v, vehicle_time_us)) * 1e-6 + v.status.clock_offset_s;
}

void GroundLink::update_link_quality(Vehicle& v, double now_s) const {
  // The arrivals are in time order in the ring: count back from the newest.
  std::size_t in_window = 0;
  for (std::size_t k = 1; k <= v.heartbeat_count; ++k) {
    const double t = v.heartbeat_times[(v.next_heartbeat_slot + kHeartbeatHistory - k) % kHeartbeatHistory];
    if (now_s - t >= config_.link_quality_window_s) break;
    ++in_window;
  }
  const double expected = config_.link_quality_window_s / config_.vehicle_heartbeat_period_s;
  v.status.link_quality = std::min(1.0, static_cast<double>(in_window) / expected);
}

// ---------------------------------------------------------------------------------------
// Sending
// ---------------------------------------------------------------------------------------
void GroundLink::tick(double now_s) {
  require_finite(now_s, "tick");
  if (due(heartbeat_started_, next_heartbeat_s_, config_.heartbeat_period_s, now_s)) {
    for (Vehicle& v : vehicles_) {
      Frame f;
      encode(GsHeartbeat{ground_time_ms(now_s), config_.session, ground_state_, heartbeat_seq_},
             v.status.vehicle.node(), f);
      send(v, f);
    }
    heartbeat_seq_ = static_cast<std::uint8_t>(pa::HeartbeatSeq::next(heartbeat_seq_));
  }
  for (Vehicle& v : vehicles_) {
    // Only a vehicle heard from: its reply's clock is unwrapped near the heartbeat's uptime.
    if (v.status.heard && due(v.timesync_started, v.next_timesync_s, config_.timesync_period_s, now_s)) {
      OutstandingRequest& r = v.requests[v.next_request_slot];  // the oldest: its reply is overdue
      v.next_request_slot = (v.next_request_slot + 1) % kTimesyncOutstanding;
      r = OutstandingRequest{true, ground_time_us(now_s), now_s};
      Frame f;
      encode(TimesyncRequest{r.ground_time_us, v.timesync_seq++}, v.status.vehicle.node(), f);
      send(v, f);
    }
    tick_commands(v, now_s);
    tick_kill(v, now_s);
    v.status.lost = !v.status.heard || now_s - v.status.last_heard_s > config_.vehicle_timeout_s;
    update_link_quality(v, now_s);
  }
}

void GroundLink::tick_commands(Vehicle& v, double now_s) {
  for (CommandRecord& r : v.commands) {
    if (r.serial == 0 || r.outcome.state != CommandState::pending || !reached(now_s, r.next_send_s)) continue;
    if (r.outcome.attempts >= config_.command_attempts) {
      r.outcome.state = CommandState::timed_out;
      continue;
    }
    send(v, r.frame);  // the same sequence: the vehicle's ack names the command either way
    ++r.outcome.attempts;
    r.next_send_s = now_s + config_.command_retry_s;
  }
}

bool GroundLink::kill_confirmed(const Vehicle& v, std::uint64_t heartbeats_at_kill) {
  return v.status.heartbeats_received > heartbeats_at_kill && v.status.mode == Mode::killed;
}

void GroundLink::tick_kill(Vehicle& v, double now_s) {
  KillRepeat& kill = v.kill;
  if (!kill.active) return;
  if (kill_confirmed(v, v.heartbeats_at_kill) || kill.sends_left <= 0) {
    kill.active = false;
    return;
  }
  if (!kill.next_set) {
    kill.next_set = true;
    kill.next_s = now_s + config_.command_retry_s;
    return;
  }
  if (!reached(now_s, kill.next_s)) return;
  send(v, kill.frame);
  --kill.sends_left;
  kill.next_s = now_s + config_.command_retry_s;
}

gs::model::VehicleInput GroundLink::send_setpoint(pa::VehicleId id, const gs::model::VehicleInput& input) {
  Vehicle& v = vehicle(id);
  if (!std::isfinite(input.a_q_mps2) || !input.omega_radps.allFinite())
    throw std::invalid_argument("GroundLink::send_setpoint: non-finite input");
  const auto seq = static_cast<std::uint8_t>(pa::SetpointSeq::next(v.setpoint_seq));
  const RateThrust sp{{to_frame_value(input.omega_radps.x()), to_frame_value(input.omega_radps.y()),
                       to_frame_value(input.omega_radps.z())},
                      to_frame_value(input.a_q_mps2),
                      seq};
  Frame f;
  encode(sp, id.node(), f);  // finite values and a vehicle node: always encodes
  v.setpoint_seq = seq;
  v.status.setpoint_seq_sent = seq;
  send(v, f);  // a refused frame is counted; the next one is still newer for the vehicle

  // What the vehicle will decode, exactly.
  Message m;
  decode(f, m);
  gs::model::VehicleInput carried;
  carried.a_q_mps2 = m.rate_thrust.thrust_mps2;
  carried.omega_radps =
      Eigen::Vector3d(m.rate_thrust.rate_radps[0], m.rate_thrust.rate_radps[1], m.rate_thrust.rate_radps[2]);
  return carried;
}

CommandHandle GroundLink::send_command(pa::VehicleId id, CommandCode code, std::int32_t argument,
                                       double now_s) {
  require_finite(now_s, "send_command");
  Vehicle& v = vehicle(id);
  const auto raw_code = static_cast<std::uint8_t>(code);
  if (raw_code == 0 || raw_code > kCommandCodeMax)
    throw std::invalid_argument("GroundLink::send_command: unknown command");

  // At most kMaxPendingCommands in flight: give up on the oldest. Then reuse a free slot or the
  // oldest resolved one (there is always one: fewer are pending than there are slots).
  CommandRecord* oldest_pending = nullptr;
  std::size_t pending = 0;
  for (CommandRecord& r : v.commands) {
    if (r.serial == 0 || r.outcome.state != CommandState::pending) continue;
    ++pending;
    if (oldest_pending == nullptr || r.serial < oldest_pending->serial) oldest_pending = &r;
  }
  if (pending >= kMaxPendingCommands) {
    oldest_pending->outcome.state = CommandState::timed_out;
    ++counters_.commands_evicted;
  }
  CommandRecord* slot = nullptr;
  for (CommandRecord& r : v.commands) {
    if (r.serial != 0 && r.outcome.state == CommandState::pending) continue;
    if (slot == nullptr || r.serial < slot->serial) slot = &r;
  }

  const std::uint8_t seq = v.command_seq;
  v.command_seq = static_cast<std::uint8_t>(pa::CommandSeq::next(v.command_seq));
  CommandRecord& r = *slot;
  r = CommandRecord{};
  r.serial = ++command_serial_;
  r.sequence = seq;
  encode(Command{code, seq, config_.session, argument}, id.node(), r.frame);
  r.outcome.state = CommandState::pending;
  r.outcome.code = code;
  r.outcome.attempts = 1;
  r.next_send_s = now_s + config_.command_retry_s;
  if (code == CommandCode::disarm) {
    // DISARM is how the operator clears a KILL: the repeats must not kill the vehicle again.
    v.kill.active = false;
  }
  send(v, r.frame);
  return CommandHandle{id, seq, r.serial};
}

CommandOutcome GroundLink::command_outcome(const CommandHandle& handle) const {
  const int i = index_of(handle.vehicle.node());
  if (i < 0 || handle.serial == 0) return CommandOutcome{};
  for (const CommandRecord& r : vehicles_[static_cast<std::size_t>(i)].commands)
    if (r.serial == handle.serial && r.sequence == handle.sequence) return r.outcome;
  return CommandOutcome{};
}

void GroundLink::send_kill(pa::VehicleId id, KillReason reason) {
  Vehicle& v = vehicle(id);
  Frame f;
  if (!encode(Kill{config_.session, reason}, id.node(), f))
    throw std::invalid_argument("GroundLink::send_kill: unknown reason");
  v.heartbeats_at_kill = v.status.heartbeats_received;
  v.kill = KillRepeat{config_.command_attempts > 1, f, config_.command_attempts - 1, false, 0.0};
  send(v, f);
}

void GroundLink::send_kill_all(KillReason reason) {
  for (const pa::VehicleId id : ids_) send_kill(id, reason);
}

}  // namespace gs::link
