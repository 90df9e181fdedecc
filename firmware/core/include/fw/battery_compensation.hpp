// The battery's voltage, measured (the flight image's VBAT ADC, a HIL_BATTERY frame in the HIL),
// validated, low-pass filtered, and the factor on the motor commands that keeps the delivered
// thrust at the commanded one as the pack sags.
//
// The law. A motor command is a thrust fraction at the reference voltage V_ref
// (BatteryConfig::reference_voltage_V, where motor_thrust_max_N was measured: thrust tables are
// made at the full pack's voltage). A brushless motor turns at a speed roughly proportional to
// the voltage its ESC applies, duty x V, and a propeller's static thrust goes with its speed
// squared, so T ~ (duty x V)^2. A command c asks for c x T_max, which at V_ref takes the duty
// sqrt(c); at V the same thrust takes the duty sqrt(c) x V_ref / V, i.e. the command
//     c' = c x (V_ref / V)^2.
// So every motor's thrust ceiling at V is T_max x (V / V_ref)^2: the mixer allocates against
// that ceiling (Mixer::set_thrust_scale), which both applies the factor and keeps its priority
// when a compensated command would exceed 1 (roll and pitch first, then collective, then yaw:
// the collective gives way, never the attitude). The same law in practice: the Crazyflie
// (motors.c, motorsCompensateBatteryVoltage) turns each thrust into the voltage the motor needs
// for it and sends that voltage over the supply voltage as its duty, capped at full; PX4
// (Battery::scale, MC_BAT_SCALE_EN) scales the rate controller's thrust and torques by
// V_charged / V, limited to 1..1.3. Ours is PX4's ratio squared because our command is a thrust
// fraction where PX4's is (after its thrust curve) closer to a duty.
//
// Why the voltage is filtered: an ADC on a divider sees the ESCs' ripple and the sag of each
// thrust change; 0.1 s follows a throw's sag within its 0.1-0.3 s and averages ten readings.
// The loop the compensation closes (more command, more current, more sag, more command) has a
// gain of about 2 x 1.5 x I R / V: 0.04 for a 3S pack of 40 mOhm hovering at 4 A, far below 1.
//
// Validation: a reading outside kValidMin..kValidMax of V_ref (a disconnected or shorted
// divider, a pack of another cell count, a broken frame) is counted and not used. Without a
// valid reading for kStale_us (none yet, the ADC or the plant silent) the factor is 1 and
// active() false: the motors get the thrust map of V_ref, never a crash; flight goes on with
// the ground station's thrust-gain estimate taking up the sag as before. The factor is limited
// to kFactorMax: below V_ref / sqrt(kFactorMax) the pack is empty and more command would only
// saturate the motors sooner.
//
// Cost: on_voltage_mv() runs once per reading (100 Hz), outside the 1 kHz tick on the ports,
// with one division and a square; check_stale() is a subtraction and a comparison; the tick
// itself pays nothing (the mixer's ceiling changes with the factor). No heap; every call bounded.
#pragma once

#include <cstdint>

#include "fw/config.hpp"

namespace fw {

class BatteryCompensation {
 public:
  static constexpr float kValidMin = 0.6f;   // of V_ref: 2.5 V a cell for a 3S reference
  static constexpr float kValidMax = 1.15f;  // of V_ref: 4.83 V a cell (a 4.35 V HV cell fits)
  static constexpr float kFactorMax = 1.5f;  // (V_ref / V)^2 at V = 0.82 V_ref, 3.43 V a cell
  static constexpr float kFilterTime_s = 0.1f;
  static constexpr std::uint32_t kStale_us = 500000;  // 50 readings at 100 Hz
  // A reading's time step is clamped into this range (the first after a gap restarts the filter).
  static constexpr float kDtMin_s = 0.001f;
  static constexpr float kDtMax_s = 0.1f;

  explicit BatteryCompensation(const BatteryConfig& config);

  // A reading of the pack's terminal voltage, at `now_us` on the vehicle's clock. Returns true
  // when it changed factor() (the caller then updates the mixer's ceiling).
  bool on_voltage_mv(std::uint16_t voltage_mv, std::uint32_t now_us);
  // Drops a reading older than kStale_us. Returns true when that changed factor().
  bool check_stale(std::uint32_t now_us);

  // (V_ref / V_filtered)^2 within [1 / kValidMax^2, kFactorMax]; 1 when not active().
  float factor() const { return factor_; }
  // A valid, fresh reading is being used (and compensation is configured: V_ref > 0).
  bool active() const { return active_; }
  // The filtered voltage for telemetry (mV); 0 when not active().
  std::uint16_t filtered_mv() const { return filtered_mv_; }
  // Readings refused as out of range, saturating.
  std::uint32_t rejected() const { return rejected_; }

 private:
  void drop();

  float reference_V_ = 0;
  float valid_min_V_ = 0;
  float valid_max_V_ = 0;
  bool configured_ = false;
  bool active_ = false;
  float filtered_V_ = 0;
  float factor_ = 1.0f;
  std::uint16_t filtered_mv_ = 0;
  std::uint32_t last_us_ = 0;
  std::uint32_t rejected_ = 0;
};

}  // namespace fw
