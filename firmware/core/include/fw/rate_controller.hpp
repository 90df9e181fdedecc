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
  Vec3 update(const Vec3& rate_setpoint_radps, const Vec3& gyro_radps, float dt_s,
              std::uint8_t saturation_flags);

  // Clears the integrators and the held output (e.g. on arming).
  void reset();

  // The integral term I per axis, in rad/s^2 (angular acceleration, before the inertia).
  const Vec3& integrator() const { return integrator_radps2_; }

 private:
  float axis_step(int axis, float setpoint_radps, float gyro_radps, float dt_s, std::uint8_t saturation_flags,
                  float& integrator_radps2) const;

  RateControllerConfig config_;
  Vec3 inertia_kgm2_{};
  Vec3 integrator_radps2_{};
  Vec3 last_torque_Nm_{};
};

}  // namespace fw
