// Vehicle firmware configuration with its documented defaults.
//
// The paper leaves the vehicle open (docs/paper-notes.md): the defaults describe a modified AscTec
// Hummingbird with a catching plate, the paper's platform. Collective thrust reaches about
// 1-24 m/s^2 and body rates are limited to 10 rad/s, typical of that platform.
#pragma once

#include <cstdint>

#include "pa/constants.hpp"
#include "pa/link_auth.hpp"
#include "pa/vehicle_id.hpp"

namespace fw {

struct AirframeConfig {
  float mass_kg = 0.52f;                                // vehicle with plate and battery
  float inertia_kgm2[3] = {2.5e-3f, 2.5e-3f, 4.5e-3f};  // principal, about x, y, z
  float arm_length_m = 0.17f;                           // centre to each motor
  float yaw_moment_per_thrust_m = 0.016f;               // rotor drag torque / thrust
  float motor_thrust_min_N = 0.08f;                     // idle: motors keep spinning when armed
  float motor_thrust_max_N = 3.2f;
  // The first-order lag of thrust the airframe was designed for: the rate gains, the impact
  // detector and the ground station's models assume it, and the motors are made to respond with
  // it whatever their own lag (motor_lag_equaliser.hpp).
  float motor_time_constant_s = 0.03f;
};

struct RateControllerConfig {
  // Angular-acceleration gains per axis (x, y, z); torque = inertia * (kp e + ki int e).
  float kp_per_s[3] = {40.0f, 40.0f, 12.0f};  // ~27 rad/s crossover with the 30 ms motor lag
  float ki_per_s2[3] = {40.0f, 40.0f, 10.0f};
  float integrator_limit_radps2[3] = {20.0f, 20.0f, 8.0f};  // |ki int e| bound
  float rate_limit_radps = 10.0f;                           // setpoints are clamped to this
  float dt_min_s = 0.0002f;                                 // dt is clamped into [min, max]
  float dt_max_s = 0.005f;
};

struct ImpactDetectorConfig {
  // The residual is the measured specific force minus the thrust the motors are expected to
  // produce: the commanded collective through the first-order motor lag
  // (AirframeConfig::motor_time_constant_s). An event is measured against the residual a few
  // samples before it rose, so anything that changes the residual slowly - a mass mismatch, a
  // sagging battery, the pole's weight after a catch, a thrust ramp the lag model gets slightly
  // wrong, the floor taking the weight at take-off - never starts one; only a change of
  // trigger_mps2 within reference_delay_samples does. (A slow bias estimate would tolerate drifts
  // of trigger / time constant, about 30 m/s^3; this tolerates trigger / delay, about 1500 m/s^3.)
  // 4 ms at 1 kHz, 1..8; an impact's rise to the trigger must fit in it
  std::uint8_t reference_delay_samples = 4;
  // the rising edge starts where the residual leaves this band (20 sigma of IMU noise)
  float onset_mps2 = 1.0f;
  float trigger_mps2 = 6.0f;         // |residual change| above this starts an event
  std::uint8_t confirm_samples = 2;  // consecutive samples above trigger to confirm, 1..7
  float release_mps2 = 3.0f;         // the event ends when the residual change falls back below this
  // A 0.03 kg pole on the absorber pushes along -z and turns the vehicle by at most a few
  // rad/s; caught at the optimal catching instant, falling at ~5 m/s onto the plate, it peaked
  // at 60.3 m/s^2 on the HIL plant (the closed-loop series, `hil fly`); a vehicle hitting the
  // floor or an obstacle exceeds one of these.
  float crash_peak_mps2 = 80.0f;  // peaks above this are crashes, in any direction ...
  // ... except the floor pushing up the body z-axis while the vehicle descends to land (the
  // failsafe descent): stiff feet touching down at the descent rate peak near 100 m/s^2, with a
  // lateral part from the floor's friction on drifting feet (91 and 44 m/s^2 at 0.33 m/s on the
  // HIL plant, tests/hil/sil_firmware_vehicle_test.cpp), so a touchdown is a crash only above
  // this peak or by crash_rate_radps (tipping over).
  float touchdown_crash_peak_mps2 = 250.0f;
  float crash_lateral_mps2 = 25.0f;  // lateral specific force change above this is a crash
  float crash_rate_radps = 15.0f;    // body-rate change during the event above this is a crash
  float catch_axis_fraction =
      0.7f;  // a catch pushes down: -z component >= this fraction of the peak (45 deg)
  std::uint32_t event_window_us = 20000;  // an event is classified at the latest this long after its onset
  // after an event, only crash-level changes start a new one for this long
  std::uint32_t refractory_us = 100000;
  float dt_min_s = 0.0002f;  // the motor-lag model's step is clamped into [min, max]
  float dt_max_s = 0.02f;
};

struct CatchReactionConfig {
  // What the vehicle does on its own after a catch, until the ground station says
  // CATCH_HANDLED or the reaction times out.
  float thrust_add_mps2 = 0.6f;        // about the pole's weight m_p g / m_vehicle
  bool hold_level = false;             // true: replace the rate setpoints by a levelling law
  std::uint32_t duration_us = 300000;  // the reaction ends by itself after this
};

struct SupervisorConfig {
  std::uint32_t setpoint_timeout_us = 20000;  // stale stream -> a hold: levelled hover (within 25 ms)
  // The link is lost after 0.3 s of silence, on both ends (the ground station's vehicle timeout
  // is the same): shorter silences are a radio fading (outages of 100 ms, two or three back to
  // back), which the vehicle rides out in a hold; longer is a dead ground station.
  // A hold this long is the failsafe hover (a dead ground station: 0.32 s after its last setpoint).
  std::uint32_t hold_max_us = 300000;
  // Lost ground heartbeat -> failsafe. The ground station reads this flag in VEHICLE_HEARTBEAT as
  // "the vehicle hears us" (docs/groundstation.md), so it too must outlast a fading radio.
  std::uint32_t heartbeat_timeout_us = 300000;
  std::uint32_t imu_timeout_us = 5000;  // IMU unhealthy this long -> IMU lost (motors off in the air)
  std::uint32_t hover_before_descent_us = 500000;  // failsafe hover lasts 0.5 s, then descent
  std::uint32_t descent_max_us = 30000000;         // give up waiting for ground contact (from 6 m: 12 s)
  float takeoff_thrust_mps2 = 2.0f;                // a fresh setpoint above this means flying
  float arming_thrust_max_mps2 = 0.0f;             // arming requires the setpoint at or below this
  float descent_rate_mps = 0.5f;                   // controlled descent speed
  float level_gain_per_s = 6.0f;                   // levelling law: rate = -gain * tilt
  float ground_contact_mps2 = 1.2f;                // extra specific force meaning the floor holds us
                                                   // (below the descent law's 2 m/s^2 at rest)
  std::uint32_t ground_contact_us = 300000;        // ... sustained this long
};

struct BatteryConfig {
  // The pack voltage at which the thrust map (AirframeConfig::motor_thrust_max_N, and so every
  // motor command's thrust fraction) holds: thrust tables are measured at the full pack's
  // voltage, 12.6 V for a 3S LiPo such as the paper's platform flies. The motor commands are
  // scaled by (V_ref / V)^2 as the measured voltage V falls (fw/battery_compensation.hpp).
  // 0 turns the compensation off (the commands are then those of V_ref whatever V reads).
  float reference_voltage_V = 12.6f;
};

struct LinkConfig {
  pa::VehicleId vehicle = pa::kVehicle1;  // this vehicle: its node id on the bus, 1..14
  // The authenticated link (pa/link_auth.hpp): the vehicle's key, provisioned at flashing time
  // (all zeros: none, and no ground frame is accepted), and this boot's session nonce, drawn
  // by the port from its entropy source.
  pa::auth::Key key{};
  std::uint32_t session_nonce = 0;
  std::uint32_t link_session_period_us = pa::kLinkSessionPeriod_us;
  std::uint32_t heartbeat_period_us = pa::kVehicleHeartbeatPeriod_us;
  std::uint32_t telemetry_rates_period_us = pa::kTelemetryRatesPeriod_us;
  std::uint32_t telemetry_attitude_period_us = pa::kTelemetryAttitudePeriod_us;
  std::uint32_t telemetry_motors_period_us = pa::kTelemetryMotorsPeriod_us;
  std::uint32_t telemetry_status_period_us = pa::kTelemetryStatusPeriod_us;
};

struct VehicleConfig {
  AirframeConfig airframe{};
  RateControllerConfig rate{};
  ImpactDetectorConfig impact{};
  CatchReactionConfig catch_reaction{};
  SupervisorConfig supervisor{};
  BatteryConfig battery{};
  LinkConfig link{};
};

}  // namespace fw
