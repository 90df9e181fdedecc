// Body-rate controller: tracks the commanded body rates Omega_q on the gyro.
//
// The paper's vehicles take collective thrust and body rates as inputs and track the rates on
// board with a high-bandwidth loop on gyroscope feedback, so that the planners can neglect the
// rotational dynamics (Section II-A, inputs (7) bounded by (2)). This is that loop: a PI law per
// axis on the rate error gives an angular acceleration, which the inertia turns into the torque
// the mixer allocates.
//
//   torque = J (kp e + I),   I = integral of ki e dt, |I| <= integrator_limit_radps2,
//   e = clamp(setpoint, +-rate_limit_radps) - gyro.
//
// Anti-windup (PX4 style): the mixer's saturation flags from the previous tick freeze each
// integrator in the direction its axis is saturated; it may still move the other way.
//
// J is the airframe file's until the ground station identifies the vehicle's own roll and pitch
// inertia (COMMAND set_inertia_scale): real airframes differ from their file by up to 20 %, and
// the loop's gain goes with J_used / J_true. A vehicle 20 % lighter in inertia than its file rang
// with the ground's throw TV-LQR at ~5 Hz and threw short (hil campaign --attempts 1000 on the
// arena envelope: throwers at 0.8-0.88 of the file's inertia caught 159 of 217, the rest 89 %;
// with their identified inertia on board, 190 of 217). Yaw keeps the file's: the identification
// flies roll and pitch only.
#pragma once

#include <cstdint>

#include "fw/config.hpp"
#include "fw/types.hpp"

namespace fw {

class RateController {
 public:
  RateController(const RateControllerConfig& config, const AirframeConfig& airframe);

  // One control step; returns the body torque request in N m (x, y, z).
  // dt_s is clamped into [dt_min_s, dt_max_s] (zero or negative dt counts as dt_min_s).
  // A non-finite setpoint, gyro or dt is rejected: the previous valid output is returned and the
  // integrators are left untouched. The same holds if the result itself would be non-finite.
  // saturation_flags are the mixer's fw::saturation bits from the previous tick.
  Vec3f update(const Vec3f& rate_setpoint_radps, const Vec3f& gyro_radps, float dt_s,
               std::uint8_t saturation_flags);

  // Clears the integrators and the held output (e.g. on arming).
  void reset();

  // The roll and pitch inertia over the airframe file's (identified on the ground); false, and
  // nothing changes, when not finite or outside kMinInertiaScale..kMaxInertiaScale.
  static constexpr float kMinInertiaScale = 0.5f;
  static constexpr float kMaxInertiaScale = 2.0f;
  bool set_inertia_scale(float scale);
  float inertia_scale() const { return inertia_scale_; }

  // The integral term I per axis, in rad/s^2 (angular acceleration, before the inertia).
  const Vec3f& integrator() const { return integrator_radps2_; }

 private:
  float axis_step(int axis, float setpoint_radps, float gyro_radps, float dt_s, std::uint8_t saturation_flags,
                  float& integrator_radps2) const;

  RateControllerConfig config_;
  Vec3f airframe_inertia_kgm2_{};
  Vec3f inertia_kgm2_{};  // the one the law uses
  float inertia_scale_ = 1.0f;
  Vec3f integrator_radps2_{};
  Vec3f last_torque_Nm_{};
};

}  // namespace fw
