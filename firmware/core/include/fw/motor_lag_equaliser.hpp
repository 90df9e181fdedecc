// Makes the motors respond with the lag the airframe was designed for, whatever their own.
//
// Every model of the vehicle assumes one first-order lag tau_d from a thrust command to the thrust
// (AirframeConfig::motor_time_constant_s): the rate gains' damping (rate_controller.hpp: a natural
// frequency sqrt(kp / tau) and a damping 1 / (2 sqrt(kp tau))), the impact detector's expected
// thrust, and on the ground the observer's rate model and the throw's TV-LQR. Real motors and
// propellers lag by 20-60 ms. At 50-60 ms the rate loop's damping fell from 0.46 to 0.32, and
// during the throw the ground's TV-LQR and the rate loop oscillated at ~3.5 Hz with the pitch
// rate saturating at 10 rad/s; the pole left the plate (measured, `hil fly --throws 10` on the
// corner hil/config/envelope/motors_60ms.yaml: 0 of 9 caught).
//
// So, between the controllers and the mixer, the request u (collective and torques) passes a
// lead-lag with the motors' identified lag tau_m:
//   y = (1 + tau_m s) / (1 + tau_d s) u,   then the motors' 1 / (1 + tau_m s) leave 1 / (1 + tau_d s),
// which is exact for a first-order motor: the vehicle responds as designed, and nothing upstream
// or on the ground needs to know tau_m. Implemented as y = r u + (1 - r) z with r = tau_m / tau_d
// and z the request low-passed with tau_d (expand it: the same transfer). Measured with the lag
// known to 10 %: 9 of 9 caught at 50 and 60 ms (tau_m set 10 % off either way), and at 20 ms.
// Applied to the request rather than to each motor, so that the mixer's saturation priority and
// the rate loop's anti-windup see what is really asked of the motors.
//
// tau_m comes from the ground station's identification (COMMAND set_motor_time_constant) and is
// the design lag until then; with tau_m = tau_d the request passes unchanged, bit for bit.
// INDI controllers invert the motor model the same way (Smeur et al., JGCD 2016).
#pragma once

#include <cmath>

#include "fw/mixer.hpp"

namespace fw {

class MotorLagEqualiser {
 public:
  // Identified lags outside this range are refused: they are not a propeller motor's.
  static constexpr float kMinTimeConstant_s = 0.01f;
  static constexpr float kMaxTimeConstant_s = 0.1f;
  // dt is clamped into this range (zero, negative and non-finite dt count as the minimum).
  static constexpr float kDtMin_s = 0.0002f;
  static constexpr float kDtMax_s = 0.005f;

  // `design_time_constant_s`: the airframe's (a valid configuration, AirframeConfig).
  explicit MotorLagEqualiser(float design_time_constant_s);

  // The motors' identified lag; false, and nothing changes, when not finite or out of range.
  bool set_motor_time_constant(float time_constant_s);
  float motor_time_constant_s() const { return motor_s_; }
  float design_time_constant_s() const { return design_s_; }

  // The request to give the mixer this tick, in place. Inline: the 1 kHz loop calls it every
  // tick, and with the design's lag it costs a comparison. A non-finite request passes unchanged
  // (the mixer refuses it) and leaves the filter as it was.
  void equalise(MixerInput& request, float dt_s) {
    if (ratio_ == 1.0f) return;
    if (!std::isfinite(request.thrust_N) || !std::isfinite(request.torque_Nm[0]) ||
        !std::isfinite(request.torque_Nm[1]) || !std::isfinite(request.torque_Nm[2]))
      return;
    if (!started_) {  // at rest on the request: no kick when the motors start or the lag is set
      lowpassed_ = request;
      started_ = true;
      return;
    }
    const float a = (dt_s >= kDtMin_s ? (dt_s <= kDtMax_s ? dt_s : kDtMax_s) : kDtMin_s) / design_s_;
    lowpassed_.thrust_N += a * (request.thrust_N - lowpassed_.thrust_N);
    request.thrust_N = ratio_ * request.thrust_N + (1.0f - ratio_) * lowpassed_.thrust_N;
    for (int i = 0; i < 3; ++i) {
      lowpassed_.torque_Nm[i] += a * (request.torque_Nm[i] - lowpassed_.torque_Nm[i]);
      request.torque_Nm[i] = ratio_ * request.torque_Nm[i] + (1.0f - ratio_) * lowpassed_.torque_Nm[i];
    }
  }

  // The motors stopped: the next request starts the filter at rest on itself.
  void reset() { started_ = false; }

 private:
  float design_s_;
  float motor_s_;
  float ratio_ = 1.0f;  // tau_m / tau_d
  bool started_ = false;
  MixerInput lowpassed_{};
};

}  // namespace fw
