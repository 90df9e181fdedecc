#include "fw/rate_controller.hpp"

#include "fw/float_ops.hpp"

namespace fw {

RateController::RateController(const RateControllerConfig& config, const AirframeConfig& airframe)
    : config_(config),
      airframe_inertia_kgm2_{airframe.inertia_kgm2[0], airframe.inertia_kgm2[1], airframe.inertia_kgm2[2]},
      inertia_kgm2_(airframe_inertia_kgm2_) {}

bool RateController::set_inertia_scale(float scale) {
  // The comparisons are false for NaN.
  if (!(scale >= kMinInertiaScale && scale <= kMaxInertiaScale)) return false;
  inertia_scale_ = scale;
  inertia_kgm2_[0] = airframe_inertia_kgm2_[0] * scale;
  inertia_kgm2_[1] = airframe_inertia_kgm2_[1] * scale;
  return true;
}

// One axis of the law (written out per axis rather than looped, which the compiler would not
// unroll): returns the torque and advances the axis' integrator unless it is frozen.
[[gnu::always_inline]] inline float RateController::axis_step(int axis, float setpoint_radps,
                                                              float gyro_radps, float dt_s,
                                                              std::uint8_t saturation_flags,
                                                              float& integrator_radps2) const {
  const float error_radps = clamp_symmetric(setpoint_radps, config_.rate_limit_radps) - gyro_radps;

  // The output uses the integral up to the previous tick (PX4 order), so a saturated tick's
  // own error is the one the freeze below decides about.
  const float torque_Nm = inertia_kgm2_[axis] * (config_.kp_per_s[axis] * error_radps + integrator_radps2);

  const float step_radps2 = config_.ki_per_s2[axis] * error_radps * dt_s;
  const bool frozen_up = (saturation_flags & saturation::positive(axis)) != 0 && step_radps2 > 0.0f;
  const bool frozen_down = (saturation_flags & saturation::negative(axis)) != 0 && step_radps2 < 0.0f;
  if (!frozen_up && !frozen_down) {
    integrator_radps2 =
        clamp_symmetric(integrator_radps2 + step_radps2, config_.integrator_limit_radps2[axis]);
  }
  return torque_Nm;
}

void RateController::reset() {
  integrator_radps2_ = {};
  last_torque_Nm_ = {};
}

Vec3f RateController::update(const Vec3f& rate_setpoint_radps, const Vec3f& gyro_radps, float dt_s,
                             std::uint8_t saturation_flags) {
  if (!(nonfinite_marker(rate_setpoint_radps) + nonfinite_marker(gyro_radps) + nonfinite_marker(dt_s) ==
        0.0f)) {
    return last_torque_Nm_;
  }
  const float dt_clamped_s = clampf(dt_s, config_.dt_min_s, config_.dt_max_s);

  Vec3f integrator_radps2 = integrator_radps2_;
  const Vec3f torque_Nm{axis_step(0, rate_setpoint_radps[0], gyro_radps[0], dt_clamped_s, saturation_flags,
                                  integrator_radps2[0]),
                        axis_step(1, rate_setpoint_radps[1], gyro_radps[1], dt_clamped_s, saturation_flags,
                                  integrator_radps2[1]),
                        axis_step(2, rate_setpoint_radps[2], gyro_radps[2], dt_clamped_s, saturation_flags,
                                  integrator_radps2[2])};

  if (!(nonfinite_marker(torque_Nm) + nonfinite_marker(integrator_radps2) == 0.0f)) return last_torque_Nm_;
  integrator_radps2_ = integrator_radps2;
  last_torque_Nm_ = torque_Nm;
  return torque_Nm;
}

}  // namespace fw
