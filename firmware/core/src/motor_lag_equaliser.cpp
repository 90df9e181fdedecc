#include "fw/motor_lag_equaliser.hpp"

namespace fw {

MotorLagEqualiser::MotorLagEqualiser(float design_time_constant_s)
    : design_s_(design_time_constant_s), motor_s_(design_time_constant_s) {}

bool MotorLagEqualiser::set_motor_time_constant(float time_constant_s) {
  // The comparisons are false for NaN; an airframe without a design lag has nothing to match.
  if (!(time_constant_s >= kMinTimeConstant_s && time_constant_s <= kMaxTimeConstant_s)) return false;
  if (!(design_s_ > 0.0f)) return false;
  motor_s_ = time_constant_s;
  ratio_ = motor_s_ / design_s_;
  started_ = false;
  return true;
}

}  // namespace fw
