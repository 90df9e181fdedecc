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
  retrying_ = retry_due_ = false;
  flight_.start(now_s, lag_.value(), inertia_.value());
}

void MotorEqualiser::start_retry(double now_s) {
  retrying_ = true;
  retry_due_ = false;
  flight_.start(now_s, lag_.value(), inertia_.value(), retry_amplitude_);
}

void MotorEqualiser::cancel_retry() {
  retry_due_ = false;
  if (retrying_ && flight_.running()) flight_.stop();
  retrying_ = false;
}

std::optional<estimation::IdentificationResult> MotorEqualiser::finish(double now_s) {
  std::optional<estimation::IdentificationResult> result = flight_.finish(now_s);
  if (!result) return result;
  identified_ = result;
  retry_due_ = !retrying_ && !result->identified;
  retry_amplitude_ = result->refusal == estimation::IdentificationRefusal::saturated ? kGentleAmplitude : 1.0;
  return result;
}

}  // namespace gs::runtime
