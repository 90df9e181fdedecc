#include "groundstation/runtime/motor_equaliser.hpp"

#include <cmath>

namespace gs::runtime {

std::int32_t motor_lag_argument_us(double lag_s) {
  return static_cast<std::int32_t>(std::lround(lag_s * 1e6));
}

std::int32_t inertia_scale_argument(double scale) {
  return static_cast<std::int32_t>(std::lround(scale * 1e3));
}

void OnBoardSetting::settle(link::CommandState state) {
  if (!pending_ || state == link::CommandState::pending) return;
  if (state == link::CommandState::accepted) value_ = sent_;
  pending_.reset();
}

void MotorEqualiser::start_identification(double now_s) {
  gentle_ = gentle_due_ = false;
  flight_.start(now_s, lag_.value(), inertia_.value());
}

void MotorEqualiser::start_gentle_identification(double now_s) {
  gentle_ = true;
  gentle_due_ = false;
  flight_.start(now_s, lag_.value(), inertia_.value(), kGentleAmplitude);
}

void MotorEqualiser::cancel_gentle_identification() {
  gentle_due_ = false;
  if (gentle_ && flight_.running()) flight_.stop();
  gentle_ = false;
}

std::optional<estimation::IdentificationResult> MotorEqualiser::finish(double now_s) {
  std::optional<estimation::IdentificationResult> result = flight_.finish(now_s);
  if (!result) return result;
  identified_ = result;
  gentle_due_ = !gentle_ && result->refusal == estimation::IdentificationRefusal::saturated;
  return result;
}

}  // namespace gs::runtime
