#include "fw/vehicle.hpp"

#include <cmath>

#include "fw/crash_policy.hpp"
#include "fw/float_ops.hpp"
#include "fw/saturating.hpp"
#include "pa/constants.hpp"
#include "pa/sequence.hpp"

namespace fw {

using namespace pa::proto;

namespace {
constexpr float kImuGyroLimit_radps = 40.0f;  // beyond the sensor's range: a broken sample
constexpr float kImuAccelLimit_mps2 = 200.0f;
constexpr float kNominalDt_s = 0.001f;
static_assert(InertialReference::kTrackPeriod_s == InertialReference::kTrackPeriod_ticks * kNominalDt_s);
constexpr std::int32_t kExpectCatchMax_ms = 10000;
// A quadrocopter's accelerometer reads gravity only while the vehicle rests; in flight it
// reads the thrust direction, which would pull the estimate towards "level" whatever the
// true tilt. So the tilt is corrected on the ground and integrated from the gyro in flight.
constexpr float kAttitudeGroundGain_per_s = 2.0f;

std::uint32_t ticks_for(std::uint32_t period_us) {
  const std::uint32_t t = period_us / pa::kImuPeriod_us;
  return t == 0 ? 1u : t;
}
}  // namespace

Vehicle::Vehicle(const VehicleConfig& config)
    : config_(config),
      link_(config.link, config.supervisor),
      guard_(config.link),
      attitude_(kAttitudeGroundGain_per_s),
      impacts_(config.impact, config.airframe),
      supervisor_(config.supervisor),
      failsafe_(config.supervisor),
      rate_controller_(config.rate, config.airframe),
      equaliser_(config.airframe.motor_time_constant_s),
      mixer_(config.airframe),
      battery_(config.battery),
      catch_(config.catch_reaction),
      // The static task table. Phases keep the heavier frames on different ticks.
      tasks_{{
          task(&Vehicle::send_telemetry_rates, ticks_for(config.link.telemetry_rates_period_us), 0),
          task(&Vehicle::send_heartbeat, ticks_for(config.link.heartbeat_period_us), 1),
          task(&Vehicle::send_telemetry_attitude, ticks_for(config.link.telemetry_attitude_period_us), 2),
          task(&Vehicle::send_telemetry_motors, ticks_for(config.link.telemetry_motors_period_us), 3),
          task(&Vehicle::send_telemetry_status, ticks_for(config.link.telemetry_status_period_us), 4),
          task(&Vehicle::send_link_session, ticks_for(config.link.link_session_period_us), 6),
          // Not telemetry: what the failsafe starts from, at 200 Hz on the ticks that send none.
          task(&Vehicle::track_flight, InertialReference::kTrackPeriod_ticks, 4),
      }} {}

// A task runs on the ticks whose count (1 on the first tick) is `phase` modulo `period`; the
// countdown reaches zero on exactly those ticks.
Vehicle::PeriodicTask Vehicle::task(void (Vehicle::*run)(std::uint32_t), std::uint32_t period_ticks,
                                    std::uint32_t phase_ticks) {
  const std::uint32_t first = phase_ticks % period_ticks;
  return PeriodicTask{run, period_ticks, first == 0 ? period_ticks : first};
}

void Vehicle::on_frame(const Frame& frame, std::uint32_t now_us) {
  // Ground frames wait for their AUTH in the guard, decoded (here, between ticks); the link
  // counts whatever is malformed or never meant for a vehicle.
  Message m;
  const DecodeStatus status = decode(frame, m);
  const TypeInfo* info = find_type(id_type(frame.id));
  if (status != DecodeStatus::ok || info->direction != Direction::ground_to_vehicle) {
    link_.on_frame(frame, now_us);
    return;
  }
  if (m.node == kBroadcastNode) guard_.on_unsigned();  // no AUTH can vouch for every vehicle
  if (m.node != link_.node()) return;                  // another vehicle's
  if (m.type == Type::auth) guard_.on_auth(frame);
  else guard_.on_frame(frame, m, now_us);
}

std::uint32_t Vehicle::rx_rejected() const {
  return saturate_cast<std::uint32_t>(std::uint64_t{link_.counters().rejected()} + guard_.rejected());
}

// The 1 kHz loop, top to bottom (docs/architecture.md, "One tick of the system"):
// sample -> link guard -> attitude -> link -> impact detector -> supervisor -> setpoint -> rate controller
// -> mixer -> motors, then the periodic tasks.
// Its steps below are called from here only and forced inline (even at -Os), so the loop pays
// no call overhead for being written as readable steps.
TickOutput Vehicle::tick(const ImuSample& imu) {
  const std::uint32_t now_us = imu.t_us;
  float dt_s = kNominalDt_s;
  if (started_) {
    const std::int32_t step_us = pa::elapsed_us(now_us, last_imu_us_);
    dt_s = static_cast<float>(step_us) * 1e-6f;  // the controllers clamp it into their range
  }
  started_ = true;
  last_imu_us_ = now_us;
  ++ticks_;

  accept_sample(imu);
  check_ground_frame(now_us);
  // The link's watchdogs and the sensors' health, once per tick: no frame arrives during it.
  update_inputs(now_us);
  estimate(dt_s);
  handle_link(now_us);
  const bool crash = detect_impact(now_us);
  supervise(crash);

  Vec3f rate_radps{};
  float thrust_mps2 = 0;
  choose_setpoint(dt_s, rate_radps, thrust_mps2);
  const TickOutput out = control_and_mix(dt_s, rate_radps, thrust_mps2);
  run_periodic_tasks(now_us);
  return out;
}

// A sample outside the sensor's range or not finite is not used; the last good one is held
// and the supervisor is told the IMU is unhealthy.
[[gnu::always_inline]] inline void Vehicle::accept_sample(const ImuSample& imu) {
  // all_within is false for NaN and the infinities too.
  imu_ok_ =
      all_within(imu.gyro_radps, kImuGyroLimit_radps) && all_within(imu.accel_mps2, kImuAccelLimit_mps2);
  if (imu_ok_) {
    gyro_radps_ = imu.gyro_radps;
    accel_mps2_ = imu.accel_mps2;
  }
}

// Each impact is reported twice (impact_detector.hpp): on detection, within a few ms, with a
// provisional class - the moment to start the catch reaction - and once it is over, with the
// final peak and class. Both go to the ground as IMPACT frames sharing the impact's count.
[[gnu::always_inline]] inline bool Vehicle::detect_impact(std::uint32_t now_us) {
  if (!imu_ok_) return false;
  ImpactEvent event{};
  // The failsafe descent expects the floor: its touchdown is not a crash by its peak alone.
  const bool landing = supervisor_.mode() == Mode::failsafe_descent;
  const ImpactInput input{now_us, accel_mps2_, gyro_radps_, thrust_applied_mps2_, catch_.expected(), landing};
  if (!impacts_.update(input, event)) return false;
  const bool final = event.stage == ImpactStage::classified;
  // The IMPACT takes the place of the tick's periodic frame, on the radio and in the tick's
  // instructions: an impact's report, a telemetry frame and a step of the guard's check in one
  // tick went over the budget of 1,500 (docs/hil.md).
  if (link_.send_message(Impact{event.t_us, event.peak_mps2, event.classification, final, event.count}))
    skip_due_telemetry();
  // A touchdown stops the descent: once its contact is over the vehicle rests on the floor, so
  // the vertical speed integrated since the failsafe began (which drifts with the
  // accelerometer's bias) restarts from zero, and the descent law's thrust falls under the
  // floor's support, which the ground-contact detector then sees.
  if (event.touchdown && final) failsafe_.on_touchdown();
  if (event.classification == ImpactClass::catch_impact) catch_.on_catch(now_us);
  return event.classification == ImpactClass::crash && crash_kills_;
}

[[gnu::always_inline]] inline void Vehicle::handle_link(std::uint32_t now_us) {
  KillReason kill_reason{};
  const bool killed_this_tick = link_.take_kill(kill_reason);
  if (killed_this_tick) supervisor_.kill(now_us);

  // A command waits for a tick that sends no telemetry (two or more of every ten with the default
  // periods, so at most 7 ms; never more than kCommandWaitMaxTicks whatever the periods), one a
  // tick: its acknowledgement and the mode change it may bring are the heaviest work on the ground
  // and in a landing, and with a telemetry frame on top the ARM's and the LAND's ticks went over
  // the tick's budget. (The guard passes at most one frame in three ticks, so the queue drains.)
  // A KILL supersedes the commands still waiting, as it does the frames queued before it in the
  // guard: they came before it, and are refused.
  if (link_.command_waiting()) {
    Command command{};
    if (killed_this_tick) {
      while (link_.take_command(command)) acknowledge(command, AckResult::refused, RefuseReason::killed);
      command_waited_ticks_ = 0;
    } else if ((!telemetry_due() || ++command_waited_ticks_ >= kCommandWaitMaxTicks) &&
               link_.take_command(command)) {
      command_waited_ticks_ = 0;
      handle_command(command, now_us);
    }
  }

  TimesyncRequest request{};
  std::uint32_t received_us = 0;
  if (link_.take_timesync(request, received_us)) {
    link_.send_message(TimesyncReply{request.ground_time_us, received_us});
  }

  // The catch window closes, and the on-board reaction times out, by themselves.
  catch_.update(now_us);

  // Only a vehicle on the ground with its motors off, disarmed or landed (a landing ends there,
  // and a failsafe after its ground station died), may follow a new ground station session: a
  // restarted ground station takes it over with DISARM, then ARM.
  link_.set_session_rebind(supervisor_.may_follow_new_session());
}

void Vehicle::handle_command(const Command& command, std::uint32_t now_us) {
  if (!link_.has_session() || command.session_token != link_.session_token()) {
    acknowledge(command, AckResult::refused, RefuseReason::bad_session_token);
    return;
  }
  switch (command.code) {
    case CommandCode::arm:
    case CommandCode::disarm:
    case CommandCode::land: {
      const bool land = command.code == CommandCode::land;
      if (land && (command.argument < -kLandSpeedMax_mmps || command.argument > kLandSpeedMax_mmps)) {
        acknowledge(command, AckResult::refused, RefuseReason::bad_argument);
        return;
      }
      // (An ARM needs no reset of the rate loop here: armed, the vehicle idles on the floor, whose
      // ticks reset it until lift-off.)
      const CommandResult r = supervisor_.handle_command(command.code, inputs_);
      if (r.accepted && land) {
        // The descent starts from the vertical speed motion capture measures, not from the one
        // integrated in flight: that one drifts with the accelerometer's bias over minutes, and
        // read as sinking it had a vehicle handed LAND 10 cm above the floor climb to 5 m.
        const float vz_mps = static_cast<float>(command.argument) * 1e-3f;
        inertial_.follow_vz(vz_mps);
        failsafe_.start(vz_mps);
      }
      acknowledge(command, r.accepted ? AckResult::accepted : AckResult::refused, r.reason);
      return;
    }
    case CommandCode::expect_catch:
      if (command.argument <= 0 || command.argument > kExpectCatchMax_ms) {
        acknowledge(command, AckResult::refused, RefuseReason::bad_argument);
      } else if (supervisor_.mode() != Mode::flying && supervisor_.mode() != Mode::hold) {
        acknowledge(command, AckResult::refused, RefuseReason::not_flying);
      } else {
        catch_.expect(now_us, static_cast<std::uint32_t>(command.argument));
        acknowledge(command, AckResult::accepted, RefuseReason::none);
      }
      return;
    case CommandCode::catch_handled:
      catch_.handled();
      acknowledge(command, AckResult::accepted, RefuseReason::none);
      return;
    case CommandCode::set_motor_time_constant: {
      const bool set = equaliser_.set_motor_time_constant(static_cast<float>(command.argument) * 1e-6f);
      acknowledge(command, set ? AckResult::accepted : AckResult::refused,
                  set ? RefuseReason::none : RefuseReason::bad_argument);
      return;
    }
    case CommandCode::set_inertia_scale: {
      const bool set = rate_controller_.set_inertia_scale(static_cast<float>(command.argument) * 1e-3f);
      acknowledge(command, set ? AckResult::accepted : AckResult::refused,
                  set ? RefuseReason::none : RefuseReason::bad_argument);
      return;
    }
    case CommandCode::correct_tilt: {
      // In flight the attitude integrates the gyro alone, and drifts (measured: 4.5 degrees after
      // five minutes and 30 throws and catches), which the on-board hold and failsafe would fly.
      // Only while the ground station flies the vehicle on motion capture is its up current.
      const std::int16_t x = pa::proto::tilt_x_counts(command.argument);
      const std::int16_t y = pa::proto::tilt_y_counts(command.argument);
      if (x < -pa::proto::kTiltMaxCounts || x > pa::proto::kTiltMaxCounts || y < -pa::proto::kTiltMaxCounts ||
          y > pa::proto::kTiltMaxCounts) {
        acknowledge(command, AckResult::refused, RefuseReason::bad_argument);
      } else if (supervisor_.mode() != Mode::flying) {
        acknowledge(command, AckResult::refused, RefuseReason::not_flying);
      } else {
        attitude_.correct_tilt(Vec3f{x * pa::proto::kTiltUnit, y * pa::proto::kTiltUnit, 1.0f});
        inertial_.tilt_corrected();
        acknowledge(command, AckResult::accepted, RefuseReason::none);
      }
      return;
    }
  }
}

void Vehicle::acknowledge(const Command& command, AckResult result, RefuseReason reason) {
  link_.send_message(CommandAck{command.seq, command.code, result, supervisor_.mode(), reason});
}

[[gnu::always_inline]] inline void Vehicle::update_inputs(std::uint32_t now_us) {
  inputs_.now_us = now_us;
  inputs_.heartbeat_live = link_.heartbeat_live(now_us);
  inputs_.setpoint_fresh = link_.setpoint_fresh(now_us);
  inputs_.setpoint_thrust_mps2 = link_.setpoint().thrust_mps2;
  inputs_.imu_ok = imu_ok_;
  inputs_.on_ground = failsafe_.on_ground();
  inputs_.crash = false;  // until the impact detector has run
}

// The attitude, corrected by the accelerometer on the ground only (in flight it reads the thrust
// direction, not gravity), and the biases learnt at rest.
[[gnu::always_inline]] inline void Vehicle::estimate(float dt_s) {
  const Mode mode = supervisor_.mode();
  const bool resting = mode == Mode::disarmed || mode == Mode::armed || mode == Mode::landed;
  if (resting) attitude_.set_accel_gain(kAttitudeGroundGain_per_s);
  else attitude_.set_accel_gain(0.0f);
  // Gyro-only in flight, so an uncorrected bias tilts the estimate by bias * flight time. (Two
  // tests rather than an early return: GCC lays the worst tick out 3 instructions shorter.)
  if (imu_ok_) attitude_.update(inertial_.unbiased_rate_radps(gyro_radps_), accel_mps2_, dt_s);
  if (resting && imu_ok_) inertial_.learn_at_rest(gyro_radps_, accel_mps2_);
}

// What the failsafe starts from (fw/inertial_reference.hpp), kept in flight by a periodic task
// off the ticks that send telemetry, which with the link guard's step are the longest.
void Vehicle::track_flight(std::uint32_t) {
  const Mode mode = supervisor_.mode();
  crash_kills_ = crash_stops_motors(mode, attitude_.tilt_cos(), FailsafeController::kMinTiltCos);
  if (mode == Mode::disarmed || mode == Mode::armed || mode == Mode::landed || mode == Mode::killed) {
    inertial_.rest(attitude_.quaternion());
    return;
  }
  if (mode != Mode::flying) {
    inertial_.follow_vz(failsafe_.vz_mps());
    if (!inertial_.rest_tilt_corrected()) inertial_.correct_rest_tilt(attitude_);
    return;
  }
  if (!imu_ok_) return;
  inertial_.track_flight(inertial_.up_accel_mps2(accel_mps2_, attitude_.up_in_body()), accel_mps2_);
}

[[gnu::always_inline]] inline void Vehicle::supervise(bool crash) {
  inputs_.crash = crash;
  supervisor_.update(inputs_);
  const Mode mode = supervisor_.mode();
  // On board: a hold or a failsafe, flown on the vehicle's own estimate (a hold that becomes the
  // failsafe hover goes on from its vertical speed). Checked at mode changes only: the steady
  // ticks of a failsafe are the firmware's heaviest.
  if (mode != last_mode_) {
    if (on_board_flight(mode) && !on_board_flight(last_mode_)) {
      // Motion capture is out of reach: integrate vertical velocity from here on, from the
      // speed estimated in flight.
      failsafe_.start(inertial_.flight_vz_mps());
    }
    last_mode_ = mode;
  }
  if (mode != Mode::failsafe_descent) failsafe_.clear_ground_contact();
}

[[gnu::always_inline]] inline void Vehicle::choose_setpoint(float dt_s, Vec3f& rate_radps,
                                                            float& thrust_mps2) {
  const Action action = supervisor_.action();
  switch (action) {
    case Action::motors_off:
    case Action::idle:
      rate_radps = Vec3f{};
      thrust_mps2 = 0;
      return;
    case Action::track_setpoints: {
      const RateThrust& sp = link_.setpoint();
      rate_radps = sp.rate_radps;
      thrust_mps2 = sp.thrust_mps2;
      if (catch_.active()) {
        thrust_mps2 += catch_.thrust_add_mps2();
        if (catch_.hold_level()) rate_radps = failsafe_.levelling_rates(attitude_.up_in_body());
      }
      return;
    }
    case Action::level_hover:
    case Action::descend: break;
  }

  // On board (fw/failsafe_controller.hpp): level, hold (or sink at) the vertical speed
  // integrated on board.
  const Vec3f up = attitude_.up_in_body();
  const float specific_up_mps2 = inertial_.up_accel_mps2(accel_mps2_, up);
  if (imu_ok_) failsafe_.integrate(specific_up_mps2, dt_s);
  if (catch_.expected() && supervisor_.mode() == Mode::hold) {
    // A hold inside a catch window: the plate stays where the ground station was taking it
    // (attitude held, the last thrust) rather than levelling, which would tip it off the pole's
    // path just before the pole arrives. The window is the expected-catch one, and the hold
    // still becomes the levelled failsafe hover at hold_max_us, from the speed integrated here.
    rate_radps = Vec3f{};
    thrust_mps2 = link_.setpoint().thrust_mps2;
    return;
  }
  rate_radps = failsafe_.levelling_rates(up);
  if (action == Action::level_hover) thrust_mps2 = failsafe_.hover_thrust_mps2(up);
  else thrust_mps2 = failsafe_.descend(up, specific_up_mps2, thrust_applied_mps2_, dt_s);
}

[[gnu::always_inline]] inline TickOutput Vehicle::control_and_mix(float dt_s, const Vec3f& rate_radps,
                                                                  float thrust_mps2) {
  TickOutput out{};
  if (!supervisor_.motors_enabled()) {
    rate_controller_.reset();
    equaliser_.reset();
    saturation_ = 0;
    thrust_applied_mps2_ = 0;
    motor_command_ = Motors{};
    return out;
  }
  // Idle on the floor (armed, not yet flying) the feet hold the attitude, so any rate error (a
  // gyro bias, the floor's tilt) would wind the integrators up and kick the vehicle at lift-off:
  // they learn in flight only (PX4 resets them while landed).
  if (supervisor_.action() == Action::idle) rate_controller_.reset();
  const Vec3f torque = rate_controller_.update(rate_radps, gyro_radps_, dt_s, saturation_);
  const float mass = config_.airframe.mass_kg;
  const float thrust_N = thrust_mps2 * mass;
  MixerInput request{thrust_N, torque};
  equaliser_.equalise(request, dt_s);
  const MixerOutput mixed = mixer_.mix(request);
  saturation_ = mixed.saturation;
  motor_command_ = mixed.command;
  // What reaches the thrust through the design lag (the impact detector's model): the request,
  // less what the motors could not take.
  thrust_applied_mps2_ = (thrust_N - mixed.thrust_unallocated_N) / mass;
  out.motor_command = mixed.command;
  out.motors_enabled = true;
  return out;
}

[[gnu::always_inline]] inline void Vehicle::run_periodic_tasks(std::uint32_t now_us) {
#pragma GCC unroll 8  // seven countdowns, straight-line: a loop would cost as much as its bodies
  for (PeriodicTask& task : tasks_) {
    if (--task.countdown_ticks != 0) continue;
    task.countdown_ticks = task.period_ticks;
    (this->*task.run)(now_us);
  }
}

// One step of the link guard's check of a ground frame (fw/link_guard.hpp), so its cost is
// bounded per tick; a frame that passes is acted on in this tick. In a failsafe (whose own law
// makes the heaviest ticks) a tick that will also send telemetry leaves its step to the next.
[[gnu::always_inline]] inline void Vehicle::check_ground_frame(std::uint32_t) {
  const Action action = supervisor_.action();
  if ((action == Action::level_hover || action == Action::descend) && telemetry_due()) return;
  Message verified;
  std::uint32_t received_us = 0;
  if (guard_.verify_next(verified, received_us)) link_.on_message(verified, received_us);
}

// The frames this tick's periodic tasks would send skip one period (the tasks that send none run).
void Vehicle::skip_due_telemetry() {
  for (std::size_t i = 0; i < kTelemetryTasks; ++i)
    if (tasks_[i].countdown_ticks == 1) tasks_[i].countdown_ticks += tasks_[i].period_ticks;
}

// Whether this tick's periodic tasks will send a telemetry frame.
[[gnu::always_inline]] inline bool Vehicle::telemetry_due() const {
  bool due = false;
  for (std::size_t i = 0; i < kTelemetryTasks; ++i) due = due || tasks_[i].countdown_ticks == 1;
  return due;
}

void Vehicle::note_tick_time_us(std::uint32_t us) {
  if (us > tick_time_max_us_) tick_time_max_us_ = us;
  if (us > pa::kImuPeriod_us) saturating_increment(overruns_);
}

void Vehicle::send_heartbeat(std::uint32_t now_us) {
  std::uint8_t flags = 0;
  const Mode mode = supervisor_.mode();
  if (supervisor_.motors_enabled()) flags |= kFlagArmed;
  if (imu_ok_) flags |= kFlagImuOk;
  if (inputs_.heartbeat_live) flags |= kFlagGroundHeartbeatOk;  // this tick's (same clock)
  if (inputs_.setpoint_fresh) flags |= kFlagSetpointFresh;
  if (catch_.expected()) flags |= kFlagCatchExpected;
  if (catch_.active()) flags |= kFlagImpactReaction;
  if (saturation_ != 0) flags |= kFlagSaturated;
  const VehicleHeartbeat hb{now_us / 1000u,
                            mode,
                            flags,
                            static_cast<std::uint8_t>(link_.setpoint().seq & 0x0Fu),
                            supervisor_.reason(),
                            saturate_cast<std::uint8_t>(rx_rejected())};
  link_.send_message(hb);
}

void Vehicle::send_telemetry_rates(std::uint32_t) {
  // Four bits: roll, pitch, collective, yaw could not be fully allocated.
  std::uint8_t sat = 0;
  if (saturation_ & (saturation::roll_pos | saturation::roll_neg)) sat |= 1u;
  if (saturation_ & (saturation::pitch_pos | saturation::pitch_neg)) sat |= 2u;
  if (saturation_ & (saturation::collective_high | saturation::collective_low)) sat |= 4u;
  if (saturation_ & (saturation::yaw_pos | saturation::yaw_neg)) sat |= 8u;
  link_.send_message(TelemetryRates{gyro_radps_, thrust_applied_mps2_, sat});
}

void Vehicle::send_telemetry_attitude(std::uint32_t) {
  link_.send_message(TelemetryAttitude{attitude_.quaternion()});
}

void Vehicle::send_telemetry_motors(std::uint32_t) { link_.send_message(TelemetryMotors{motor_command_}); }

void Vehicle::note_battery_mv(std::uint16_t mv) {
  if (battery_.on_voltage_mv(mv, last_imu_us_)) mixer_.set_command_factor(battery_.factor());
}

// Also the battery's housekeeping: a voltage that stopped coming is dropped here, at 10 Hz.
void Vehicle::send_telemetry_status(std::uint32_t now_us) {
  if (battery_.check_stale(now_us)) mixer_.set_command_factor(battery_.factor());
  const TelemetryStatus status{saturate_cast<std::uint16_t>(tick_time_max_us_), battery_.filtered_mv(),
                               saturate_cast<std::uint16_t>(rx_rejected()),
                               saturate_cast<std::uint8_t>(overruns_), impacts_.count()};
  tick_time_max_us_ = 0;  // the longest tick of each report period
  link_.send_message(status);
}

void Vehicle::send_link_session(std::uint32_t) {
  link_.send_message(LinkSession{guard_.nonce(), guard_.last_counter()});
}

}  // namespace fw
