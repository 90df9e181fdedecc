// The vehicle firmware's composition root: every core module wired in the fixed loop order of
// docs/architecture.md, and the static task table of the slower periodic work. A port owns one
// Vehicle (a static instance on the MCU), hands it received frames and IMU samples on one
// clock, drives the motors with what tick() returns and sends what pop_tx() yields.
// No heap; every call is bounded in time.
#pragma once

#include <array>
#include <cstdint>

#include "fw/attitude_estimator.hpp"
#include "fw/battery_compensation.hpp"
#include "fw/catch_reaction.hpp"
#include "fw/command_link.hpp"
#include "fw/config.hpp"
#include "fw/failsafe_controller.hpp"
#include "fw/impact_detector.hpp"
#include "fw/inertial_reference.hpp"
#include "fw/link_guard.hpp"
#include "fw/mixer.hpp"
#include "fw/motor_lag_equaliser.hpp"
#include "fw/rate_controller.hpp"
#include "fw/supervisor.hpp"
#include "fw/types.hpp"
#include "pa/protocol.hpp"

namespace fw {

struct TickOutput {
  Motors motor_command{};  // normalised 0..1 per motor; all zero when the motors are off
  bool motors_enabled = false;
};

class Vehicle {
 public:
  explicit Vehicle(const VehicleConfig& config);

  // Any frame read from the vehicle bus, on the same clock as the IMU samples. Ground frames
  // wait for their AUTH and are verified in the next tick (fw/link_guard.hpp).
  void on_frame(const pa::proto::Frame& frame, std::uint32_t now_us);
  // The 1 kHz loop, run by each IMU sample.
  TickOutput tick(const ImuSample& imu);
  // Frames to send, oldest first.
  bool pop_tx(pa::proto::Frame& out) { return link_.pop_tx(out); }
  // The port measures each tick and reports it; the longest is sent in TELEMETRY_STATUS.
  void note_tick_time_us(std::uint32_t us);
  // The pack's terminal voltage, read by the port (the flight image's VBAT ADC, the HIL ports'
  // HIL_BATTERY frames) about every 10 ms between ticks, on the clock of the last IMU sample:
  // the motor commands are compensated for it (fw/battery_compensation.hpp) and TELEMETRY_STATUS
  // reports it filtered. The ports take HIL_BATTERY from their own bus only: no ground frame
  // sets it (the radio is open air and this frame carries no AUTH).
  void note_battery_mv(std::uint16_t mv);
  const BatteryCompensation& battery() const { return battery_; }

  pa::proto::Mode mode() const { return supervisor_.mode(); }
  pa::proto::FailsafeReason failsafe_reason() const { return supervisor_.reason(); }
  const CommandLink& link() const { return link_; }
  const LinkGuard& guard() const { return guard_; }
  // Every frame refused since boot, by the link and by its guard (saturating).
  std::uint32_t rx_rejected() const;
  const AttitudeEstimator& attitude() const { return attitude_; }
  std::uint8_t saturation() const { return saturation_; }
  // The motors' lag as the ground station identified it (the airframe's until then).
  float motor_time_constant_s() const { return equaliser_.motor_time_constant_s(); }
  float inertia_scale() const { return rate_controller_.inertia_scale(); }
  bool catch_reaction_active() const { return catch_.active(); }
  // The accelerometer's bias along up, learnt at rest on the floor; the failsafe removes it.
  float accel_bias_up_mps2() const { return inertial_.accel_bias_up_mps2(); }
  const Vec3f& gyro_bias_radps() const { return inertial_.gyro_bias_radps(); }  // learnt at rest
  float flight_vz_mps() const { return inertial_.flight_vz_mps(); }  // the failsafe's starting speed
  std::uint8_t impact_count() const { return impacts_.count(); }
  std::uint32_t ticks() const { return ticks_; }

 private:
  // One row of the static task table: run every `period` ticks, `phase` ticks in, so that
  // no two heavy tasks share a tick (counted down rather than divided on every tick).
  struct PeriodicTask {
    void (Vehicle::*run)(std::uint32_t now_us);
    std::uint32_t period_ticks;
    std::uint32_t countdown_ticks;  // ticks until the next run, this one included
  };
  static PeriodicTask task(void (Vehicle::*run)(std::uint32_t), std::uint32_t period_ticks,
                           std::uint32_t phase_ticks);

  // The steps of tick(), in order.
  void accept_sample(const ImuSample& imu);
  void check_ground_frame(std::uint32_t now_us);
  void handle_link(std::uint32_t now_us);
  bool detect_impact(std::uint32_t now_us);  // true when the impact was a crash
  void estimate(float dt_s);
  void supervise(bool crash);
  void choose_setpoint(float dt_s, Vec3f& rate_radps, float& thrust_mps2);
  TickOutput control_and_mix(float dt_s, const Vec3f& rate_radps, float thrust_mps2);
  void run_periodic_tasks(std::uint32_t now_us);
  bool telemetry_due() const;  // whether this tick's periodic tasks send a frame
  void skip_due_telemetry();   // this tick's periodic frames wait a period

  void handle_command(const pa::proto::Command& command, std::uint32_t now_us);
  void acknowledge(const pa::proto::Command& command, pa::proto::AckResult result,
                   pa::proto::RefuseReason reason);
  void update_inputs(std::uint32_t now_us);  // inputs_ for this tick, crash false

  void send_heartbeat(std::uint32_t now_us);
  void send_telemetry_rates(std::uint32_t now_us);
  void send_telemetry_attitude(std::uint32_t now_us);
  void send_telemetry_motors(std::uint32_t now_us);
  void send_telemetry_status(std::uint32_t now_us);
  void send_link_session(std::uint32_t now_us);
  void track_flight(std::uint32_t now_us);

  VehicleConfig config_;
  CommandLink link_;
  LinkGuard guard_;
  AttitudeEstimator attitude_;
  ImpactDetector impacts_;
  Supervisor supervisor_;
  InertialReference inertial_;
  FailsafeController failsafe_;
  RateController rate_controller_;
  MotorLagEqualiser equaliser_;
  Mixer mixer_;
  BatteryCompensation battery_;
  CatchReaction catch_;  // the window in which an impact is a catch, and the on-board reaction
  static constexpr std::size_t kTelemetryTasks = 6;  // the first six send frames
  std::array<PeriodicTask, kTelemetryTasks + 1> tasks_;

  // The longest a command waits for a tick without telemetry (handle_link).
  static constexpr std::uint32_t kCommandWaitMaxTicks = 10;
  std::uint32_t command_waited_ticks_ = 0;

  bool started_ = false;
  std::uint32_t last_imu_us_ = 0;
  std::uint32_t ticks_ = 0;
  bool imu_ok_ = false;
  SupervisorInputs inputs_{};  // this tick's, from the start of tick()
  Vec3f gyro_radps_{};
  Vec3f accel_mps2_{};

  // Applied control of the last tick, for the detectors and telemetry.
  float thrust_applied_mps2_ = 0;
  std::uint8_t saturation_ = 0;
  Motors motor_command_{};

  bool crash_kills_ = true;  // whether an impact classed a crash stops the motors (track_flight)
  pa::proto::Mode last_mode_ = pa::proto::Mode::disarmed;

  std::uint32_t tick_time_max_us_ = 0;
  std::uint32_t overruns_ = 0;
};

}  // namespace fw
