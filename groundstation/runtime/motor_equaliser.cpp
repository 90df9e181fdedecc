#include "groundstation/runtime/motor_equaliser.hpp"

#include <cmath>

namespace gs::runtime {

std::int32_t motor_lag_argument_us(double lag_s) {
  return static_cast<std::int32_t>(std::lround(lag_s * 1e6));
}

void MotorEqualiser::settle(link::CommandState state) {
  if (!pending_ || state == link::CommandState::pending) return;
  if (state == link::CommandState::accepted) equalised_s_ = sent_s_;
  pending_.reset();
}

std::optional<estimation::IdentificationResult> MotorEqualiser::finish(double now_s) {
  std::optional<estimation::IdentificationResult> result = flight_.finish(now_s);
  if (result) identified_ = result;
  return result;
}

}  // namespace gs::runtime
