#include "fw/rate_controller.hpp"

#include <cmath>

namespace fw {
namespace {

float clampf(float v, float lo, float hi) { return v < lo ? lo : (v > hi ? hi : v); }

bool finite(const Vec3& v) {
  return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

}  // namespace

RateController::RateController(const RateControllerConfig& config, const AirframeConfig& airframe)
    : config_(config),
      inertia_kgm2_{airframe.inertia_kgm2[0], airframe.inertia_kgm2[1], airframe.inertia_kgm2[2]} {}

void RateController::reset() {
  integrator_radps2_ = {};
  last_torque_Nm_ = {};
}

Vec3 RateController::update(const Vec3& rate_setpoint_radps, const Vec3& gyro_radps, float dt_s,
                            std::uint8_t saturation_flags) {
  if (!finite(rate_setpoint_radps) || !finite(gyro_radps) || !std::isfinite(dt_s)) {
    return last_torque_Nm_;
  }
  const float dt_clamped_s = clampf(dt_s, config_.dt_min_s, config_.dt_max_s);
  const float limit_radps = config_.rate_limit_radps;

  Vec3 torque_Nm{};
  Vec3 integrator_radps2 = integrator_radps2_;
  for (int axis = 0; axis < 3; ++axis) {
    const float setpoint_radps = clampf(rate_setpoint_radps[axis], -limit_radps, limit_radps);
    const float error_radps = setpoint_radps - gyro_radps[axis];

    // The output uses the integral up to the previous tick (PX4 order), so a saturated tick's
    // own error is the one the freeze below decides about.
    torque_Nm[axis] =
        inertia_kgm2_[axis] * (config_.kp_per_s[axis] * error_radps + integrator_radps2[axis]);

    const float step_radps2 = config_.ki_per_s2[axis] * error_radps * dt_clamped_s;
    const bool frozen_up = (saturation_flags & saturation::positive(axis)) != 0 && step_radps2 > 0.0f;
    const bool frozen_down = (saturation_flags & saturation::negative(axis)) != 0 && step_radps2 < 0.0f;
    if (!frozen_up && !frozen_down) {
      const float bound_radps2 = config_.integrator_limit_radps2[axis];
      integrator_radps2[axis] = clampf(integrator_radps2[axis] + step_radps2, -bound_radps2, bound_radps2);
    }
  }

  if (!finite(torque_Nm) || !finite(integrator_radps2)) return last_torque_Nm_;
  integrator_radps2_ = integrator_radps2;
  last_torque_Nm_ = torque_Nm;
  return torque_Nm;
}

}  // namespace fw
