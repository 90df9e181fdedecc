// The scripted self-test flight (see selftest.hpp). The ground station's part is played by a
// short script that sends the frames a ground station would; the vehicle's frames are read
// back and checked. Times are in 1 kHz ticks.
#include "fw/selftest.hpp"

#include <cmath>

#include "fw/synthetic_vehicle.hpp"
#include "fw/vehicle.hpp"
#include "pa/constants.hpp"

namespace fw::selftest {

namespace {

using namespace pa::proto;

constexpr std::uint16_t kSession = 0x5A17;
constexpr std::uint8_t kNode = 1;
// The self-test's own link key and nonce: a test vehicle's, never a flying one's.
constexpr pa::auth::Key kLinkKey{0x53, 0x45, 0x4C, 0x46, 0x54, 0x45, 0x53, 0x54,
                                 0x2D, 0x4B, 0x45, 0x59, 0x2D, 0x30, 0x30, 0x31};
constexpr std::uint32_t kNonce = 0x5E1F7E57u;

// The script, in ticks (ms).
constexpr std::uint32_t kArmAt = 202;    // handled at 208, in the tick that finishes its check
constexpr std::uint32_t kClimbAt = 300;  // up to 1 m
constexpr std::uint32_t kHoverAt = 1700;
constexpr std::uint32_t kManoeuvreAt = 2500;  // roll and pitch rate sines
constexpr std::uint32_t kManoeuvreEnd = 3500;
constexpr std::uint32_t kExpectCatchAt = 3800;
constexpr std::uint32_t kImpactAt = 4207;  // the pole lands on the plate (detected at 4209)
constexpr std::uint32_t kImpactPulse = 8;  // half-sine contact, ms
constexpr float kImpactPeak_N = 23.6f;     // 0.03 kg at 4 m/s stopped in 8 ms
constexpr std::uint32_t kHandledAt = 4300;
constexpr std::uint32_t kTiltAt = 4800;      // a small roll so the failsafe has to level
constexpr std::uint32_t kLinkLossAt = 5000;  // setpoints repeat an old sequence from here
constexpr std::uint32_t kEnd = 9500;

constexpr std::uint32_t kSetpointPeriod = 5;  // 200 Hz
// The setpoints' phase: each is checked by the link guard over the three ticks after it, so the
// impact's detection falls in a tick that finishes a check and is due to send TELEMETRY_RATES,
// the heaviest frame: the worst tick the budget must hold. scripts/tick-profile.sh shows what a
// tick carries (docs/hil.md), should a change move these coincidences.
constexpr std::uint32_t kSetpointPhase = 2;
constexpr std::uint32_t kHeartbeatPeriod = 20;  // 50 Hz
// The battery as the flight image reads it, between ticks at 100 Hz: at the reference voltage,
// where the synthetic motors make the thrust they are commanded (the compensation's factor is
// 1, its work per tick and per reading the same as on a sagging pack).
constexpr std::uint32_t kBatteryPeriod = 10;
constexpr std::uint16_t kBattery_mv = 12600;

struct Ground {
  pa::auth::Signer signer{kLinkKey};
  std::uint8_t setpoint_seq = 0;
  std::uint8_t heartbeat_seq = 0;
  std::uint8_t command_seq = 0;
  std::uint32_t last_fresh_setpoint_tick = 0;

  Ground() { signer.start_session(kNonce, 0); }

  // The frame and its AUTH, as the ground station sends them.
  void send(Vehicle& v, const Frame& f, std::uint32_t now_us) {
    Frame auth;
    if (!signer.sign(f, auth)) return;
    v.on_frame(f, now_us);
    v.on_frame(auth, now_us);
  }

  void heartbeat(Vehicle& v, std::uint32_t tick) {
    Frame f;
    if (encode(GsHeartbeat{tick, kSession, GroundState::active, heartbeat_seq++}, kNode, f))
      send(v, f, tick * 1000u);
  }
  void setpoint(Vehicle& v, std::uint32_t tick, const Vec3f& rate, float thrust, bool fresh) {
    if (fresh) {
      setpoint_seq = static_cast<std::uint8_t>((setpoint_seq + 1) & 0x0F);
      last_fresh_setpoint_tick = tick;
    }
    Frame f;
    if (encode(RateThrust{rate, thrust, setpoint_seq}, kNode, f)) send(v, f, tick * 1000u);
  }
  void command(Vehicle& v, std::uint32_t tick, CommandCode code, std::int32_t argument) {
    Frame f;
    if (encode(Command{code, command_seq++, kSession, argument}, kNode, f)) send(v, f, tick * 1000u);
  }
};

// The ground station's part: it sees the synthetic vehicle as motion capture would and flies
// it with rate and thrust setpoints, as the real one does: a height loop (1 m above the floor),
// a levelling loop, rate sines for the manoeuvre, and a deliberate roll before the link loss
// so that the on-board failsafe has a tilt to level.
void script_setpoint(std::uint32_t tick, const SyntheticVehicle& plant, Vec3f& rate, float& thrust) {
  rate = Vec3f{};
  thrust = 0;
  if (tick < kClimbAt) return;
  constexpr float kHeight_m = 1.0f;
  const float tilt_cos = plant.tilt_cos() > 0.5f ? plant.tilt_cos() : 0.5f;
  thrust =
      (pa::kGravityFloat_mps2 + 4.0f * (kHeight_m - plant.position_m()[2]) - 3.0f * plant.velocity_mps()[2]) /
      tilt_cos;
  const Vec3f up = plant.up_in_body();
  rate = Vec3f{-3.0f * up[1], 3.0f * up[0], 0.0f};  // level
  if (tick >= kManoeuvreAt && tick < kManoeuvreEnd) {
    // One period of a 1 Hz sine on roll and pitch rates: the angles return to level.
    const float phase = 6.2831853f * static_cast<float>(tick - kManoeuvreAt) / 1000.0f;
    const float s = std::sin(phase);
    rate[0] = 1.5f * s;
    rate[1] = -1.0f * s;
  }
  if (tick >= kTiltAt && tick < kLinkLossAt) rate = Vec3f{tick < kTiltAt + 100 ? 1.5f : 0.0f, 0.0f, 0.0f};
}

}  // namespace

Result run(TickProbe* probe) {
  VehicleConfig config{};
  config.link.vehicle = pa::VehicleId(kNode);
  config.link.key = kLinkKey;
  config.link.session_nonce = kNonce;
  Vehicle vehicle(config);
  SyntheticVehicle plant(config.airframe);
  Ground ground;
  Result r;

  double manoeuvre_sq_sum = 0;
  std::uint32_t manoeuvre_samples = 0;
  bool arm_acked = false;
  bool catch_acked = false;
  bool catch_reported = false;
  bool catch_confirmed = false;
  bool misclassified = false;
  std::uint32_t hover_tick = 0, descent_tick = 0, floor_tick = 0, off_tick = 0;
  float tilt_cos_at_descent = 0;
  Motors motors{};

  for (std::uint32_t tick = 0; tick < kEnd; ++tick) {
    const std::uint32_t now_us = tick * 1000u;

    // Ground station: heartbeats throughout, setpoints at 200 Hz, commands at their times.
    if (tick % kHeartbeatPeriod == 0) ground.heartbeat(vehicle, tick);
    if (tick % kBatteryPeriod == 0) vehicle.note_battery_mv(kBattery_mv);
    Vec3f rate{};
    float thrust = 0;
    script_setpoint(tick, plant, rate, thrust);
    if (tick % kSetpointPeriod == kSetpointPhase)
      ground.setpoint(vehicle, tick, rate, thrust, tick < kLinkLossAt);
    if (tick == kArmAt) ground.command(vehicle, tick, CommandCode::arm, 0);
    if (tick == kExpectCatchAt) ground.command(vehicle, tick, CommandCode::expect_catch, 1000);
    if (tick == kHandledAt) ground.command(vehicle, tick, CommandCode::catch_handled, 0);

    // The pole: a half-sine contact pulse, then its weight rests on the plate.
    Vec3f external{};
    if (tick >= kImpactAt && tick < kImpactAt + kImpactPulse) {
      const float phase =
          3.14159265f * static_cast<float>(tick - kImpactAt) / static_cast<float>(kImpactPulse);
      external[2] = -kImpactPeak_N * std::sin(phase);
    } else if (tick >= kImpactAt + kImpactPulse && tick < kLinkLossAt) {
      external[2] = -0.03f * pa::kGravityFloat_mps2;
    }
    plant.step(motors, external, 0.001f);

    // The vehicle's tick, measured by the port's probe.
    const ImuSample imu = plant.imu(now_us);
    if (probe != nullptr) probe->before_tick();
    const TickOutput out = vehicle.tick(imu);
    if (probe != nullptr) probe->after_tick();
    motors = out.motors_enabled ? out.motor_command : Motors{};
    ++r.ticks;

    // Read what the vehicle sent.
    Frame f;
    while (vehicle.pop_tx(f)) {
      Message m;
      if (decode(f, m) != DecodeStatus::ok) {
        r.failure = "vehicle sent an undecodable frame";
        return r;
      }
      if (m.type == Type::command_ack && m.command_ack.code == CommandCode::arm)
        arm_acked = m.command_ack.result == AckResult::accepted;
      if (m.type == Type::command_ack && m.command_ack.code == CommandCode::expect_catch)
        catch_acked = m.command_ack.result == AckResult::accepted;
      if (m.type == Type::impact) {
        if (tick >= kLinkLossAt) {
          // The touchdown at the end of the descent is an impact too; not the pole's.
        } else if (m.impact.classification != ImpactClass::catch_impact) {
          misclassified = true;
        } else if (!catch_reported) {
          catch_reported = true;
          r.impact_detection_latency_ms = static_cast<float>(tick - kImpactAt);
          r.impact_timestamp_error_ms =
              (static_cast<float>(m.impact.vehicle_time_us) - static_cast<float>(kImpactAt) * 1000.0f) /
              1000.0f;
        } else if (m.impact.final) {
          catch_confirmed = true;
        }
      }
    }

    // Observations.
    const Mode mode = vehicle.mode();
    if (tick >= kHoverAt + 300 && tick < kManoeuvreAt) {
      for (int i = 0; i < 3; ++i) {
        const float e = std::fabs(plant.rate_radps()[i] - rate[i]);
        if (e > r.hover_rate_error_max_radps) r.hover_rate_error_max_radps = e;
      }
    }
    if (tick >= kManoeuvreAt && tick < kManoeuvreEnd) {
      for (int i = 0; i < 2; ++i) {
        const float e = plant.rate_radps()[i] - rate[i];
        manoeuvre_sq_sum += static_cast<double>(e * e);
        ++manoeuvre_samples;
      }
    }
    if (hover_tick == 0 && fw::action_for(mode) == fw::Action::level_hover) hover_tick = tick;  // a hold
    if (descent_tick == 0 && mode == Mode::failsafe_descent) {
      descent_tick = tick;
      tilt_cos_at_descent = plant.tilt_cos();
    }
    if (descent_tick != 0 && floor_tick == 0 && plant.on_floor()) floor_tick = tick;
    if (floor_tick != 0 && off_tick == 0 && !out.motors_enabled) off_tick = tick;
  }

  if (manoeuvre_samples > 0)
    r.manoeuvre_rate_error_rms_radps = static_cast<float>(std::sqrt(manoeuvre_sq_sum / manoeuvre_samples));
  if (hover_tick != 0)
    r.failsafe_hover_after_ms = static_cast<float>(hover_tick - ground.last_fresh_setpoint_tick);
  if (descent_tick != 0 && hover_tick != 0)
    r.descent_after_ms = static_cast<float>(descent_tick - hover_tick);
  if (off_tick != 0) r.motors_off_after_landing_ms = static_cast<float>(off_tick - floor_tick);

  // The checks, in the order the scenario meets them.
  if (!arm_acked) r.failure = "arming was not accepted";
  else if (r.hover_rate_error_max_radps > 0.05f) r.failure = "hover: body-rate error above 0.05 rad/s";
  else if (r.manoeuvre_rate_error_rms_radps > 0.3f)
    r.failure = "manoeuvre: rate tracking rms above 0.3 rad/s";
  else if (!catch_acked) r.failure = "expect-catch was not accepted";
  else if (!catch_reported) r.failure = "impact: no catch reported";
  else if (misclassified) r.failure = "impact: reported as something other than a catch";
  else if (!catch_confirmed) r.failure = "impact: no final report of the catch";
  else if (r.impact_detection_latency_ms > 5.0f) r.failure = "impact: detected later than 5 ms";
  else if (std::fabs(r.impact_timestamp_error_ms) > 1.0f)
    r.failure = "impact: timestamp off by more than 1 ms";
  else if (hover_tick == 0 || r.failsafe_hover_after_ms > 25.0f)
    r.failure = "link loss: no levelled hover within 25 ms";
  else if (descent_tick == 0 ||
           std::fabs(r.descent_after_ms - static_cast<float>(config.supervisor.hold_max_us +
                                                             config.supervisor.hover_before_descent_us) /
                                              1000.0f) > 2.0f)
    r.failure = "link loss: descent not after the hold and the failsafe hover";
  else if (tilt_cos_at_descent < 0.9994f)
    r.failure = "link loss: not level (within 2 degrees) when descending";
  else if (off_tick == 0) r.failure = "link loss: motors still on after reaching the ground";
  else if (vehicle.mode() != Mode::landed) r.failure = "link loss: not landed at the end";
  r.pass = r.failure == nullptr;
  return r;
}

}  // namespace fw::selftest
