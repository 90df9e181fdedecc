#include "fw/impact_detector.hpp"

#include <cmath>

#include "pa/sequence.hpp"

namespace fw {

using pa::proto::ImpactClass;

namespace {

bool finite3(const Vec3& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

Vec3 minus(const Vec3& a, const Vec3& b) { return Vec3{a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }

float norm(const Vec3& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

float clampf(float v, float lo, float hi) { return v < lo ? lo : (v > hi ? hi : v); }

std::uint8_t clamp_u8(std::uint8_t v, std::uint8_t lo, std::uint8_t hi) { return v < lo ? lo : (v > hi ? hi : v); }

// A config that cannot work is made to: the integer ranges the history supports, the levels in
// the order onset <= release <= trigger, a positive dt range.
ImpactDetectorConfig sanitised(ImpactDetectorConfig c) {
  c.reference_delay_samples = clamp_u8(c.reference_delay_samples, 1, ImpactDetector::kMaxReferenceDelay);
  c.confirm_samples = clamp_u8(c.confirm_samples, 1, ImpactDetector::kMaxConfirmSamples);
  if (!(c.trigger_mps2 > 0.0f)) c.trigger_mps2 = 6.0f;
  if (!(c.onset_mps2 > 0.0f) || c.onset_mps2 > c.trigger_mps2) c.onset_mps2 = c.trigger_mps2;
  if (!(c.release_mps2 > 0.0f) || c.release_mps2 > c.trigger_mps2) c.release_mps2 = c.trigger_mps2;
  if (!(c.dt_min_s > 0.0f)) c.dt_min_s = 1e-4f;
  if (!(c.dt_max_s >= c.dt_min_s)) c.dt_max_s = c.dt_min_s;
  return c;
}

}  // namespace

static_assert(ImpactDetector::kMaxReferenceDelay + ImpactDetector::kMaxConfirmSamples < ImpactDetector::kHistory,
              "the history must hold the reference and every sample up to the confirmation");

ImpactDetector::ImpactDetector(const ImpactDetectorConfig& config, const AirframeConfig& airframe)
    : config_(sanitised(config)),
      motor_time_constant_s_(airframe.motor_time_constant_s > 0.0f ? airframe.motor_time_constant_s : 0.0f) {}

void ImpactDetector::reset() {
  started_ = false;
  expected_mps2_ = 0.0f;
  history_ = {};
  newest_ = 0;
  filled_ = 0;
  phase_ = Phase::idle;
  reference_ = {};
  reference_age_ = 0;
  above_ = 0;
  crash_level_only_ = false;
  catch_expected_ = false;
  acc_ = {};
  onset_us_ = 0;
  detected_us_ = 0;
  has_last_event_ = false;
  last_event_end_us_ = 0;
  has_settled_ = false;
  settled_us_ = 0;
}

Vec3 ImpactDetector::residual_mps2() const { return filled_ == 0 ? Vec3{} : history(0).residual_mps2; }

const ImpactDetector::Sample& ImpactDetector::history(std::size_t samples_ago) const {
  return history_[(newest_ + kHistory - samples_ago) % kHistory];
}

bool ImpactDetector::update(const ImpactInput& in, ImpactEvent& out) {
  if (!finite3(in.accel_mps2) || !finite3(in.gyro_radps) || !std::isfinite(in.commanded_thrust_mps2)) return false;
  // A fixed-pitch rotor cannot pull down: a negative command means zero thrust.
  const float command_mps2 = in.commanded_thrust_mps2 > 0.0f ? in.commanded_thrust_mps2 : 0.0f;

  // 1. The thrust the motors produce now: the command through the first-order lag. The step
  //    uses 1 - exp(-x) ~ x / (1 + x/2) (no expf in the 1 kHz path), within 0.1 % for x <= 0.1.
  if (!started_) {
    expected_mps2_ = command_mps2;  // assume the motors had settled
    started_ = true;
  } else {
    const float dt_s = clampf(static_cast<float>(pa::elapsed_us(in.t_us, last_t_us_)) * 1e-6f, config_.dt_min_s,
                              config_.dt_max_s);
    float alpha = 1.0f;
    if (motor_time_constant_s_ > 0.0f) {
      const float x = dt_s / motor_time_constant_s_;
      alpha = x / (1.0f + 0.5f * x);
      if (alpha > 1.0f) alpha = 1.0f;
    }
    expected_mps2_ += alpha * (command_mps2 - expected_mps2_);
  }
  last_t_us_ = in.t_us;

  newest_ = (newest_ + 1) % kHistory;
  Sample& s = history_[newest_];
  s.t_us = in.t_us;
  s.residual_mps2 = Vec3{in.accel_mps2[0], in.accel_mps2[1], in.accel_mps2[2] - expected_mps2_};
  s.gyro_radps = in.gyro_radps;
  if (filled_ < kHistory) ++filled_;

  switch (phase_) {
    case Phase::idle: {
      // 2. Against the residual reference_delay_samples ago: only a fast change starts an event.
      const std::size_t delay = config_.reference_delay_samples;
      if (filled_ <= delay) return false;
      // The marks below are dropped once passed, so that a clock difference to an old one
      // never wraps (after 2^31 us, about 36 minutes).
      if (has_last_event_ &&
          pa::elapsed_us(in.t_us, last_event_end_us_) >= static_cast<std::int32_t>(config_.refractory_us))
        has_last_event_ = false;
      const bool refractory = has_last_event_;
      const Sample& reference = history(delay);
      // Never measure against a sample of an earlier excursion: its falling edge would look
      // like a new change.
      if (has_settled_) {
        if (pa::elapsed_us(reference.t_us, settled_us_) < 0) return false;
        has_settled_ = false;
      }
      if (!triggered(minus(s.residual_mps2, reference.residual_mps2), refractory)) return false;
      reference_ = reference;
      reference_age_ = delay;
      above_ = 1;
      crash_level_only_ = refractory;
      catch_expected_ = in.catch_expected;
      phase_ = Phase::pending;
      break;
    }
    case Phase::pending:
      ++reference_age_;
      catch_expected_ = catch_expected_ || in.catch_expected;
      if (!triggered(minus(s.residual_mps2, reference_.residual_mps2), crash_level_only_)) {
        phase_ = Phase::idle;  // a spike too short to confirm
        has_settled_ = true;
        settled_us_ = in.t_us;
        return false;
      }
      ++above_;
      break;
    case Phase::active:
    case Phase::tail: {
      catch_expected_ = catch_expected_ || in.catch_expected;
      const float change_mps2 = add(acc_, s);
      const bool released = change_mps2 < config_.release_mps2;
      const bool expired = pa::elapsed_us(in.t_us, onset_us_) >= static_cast<std::int32_t>(config_.event_window_us);
      if (released || expired) {
        // The contact is over: the refractory period runs from here.
        has_last_event_ = true;
        last_event_end_us_ = in.t_us;
        has_settled_ = true;
        settled_us_ = in.t_us;
      }
      if (phase_ == Phase::tail) {
        // A crash classified early: the rest of its contact is the same event.
        if (released || expired) phase_ = Phase::idle;
        return false;
      }
      const bool crash = crash_seen(acc_, acc_.peak_mps2);
      if (!(crash || released || expired)) return false;
      finish(released || expired, out);
      return true;
    }
  }

  if (above_ < config_.confirm_samples) return false;
  confirm(in.t_us, out);
  return true;
}

bool ImpactDetector::triggered(const Vec3& change_mps2, bool crash_level_only) const {
  const float total2 = change_mps2[0] * change_mps2[0] + change_mps2[1] * change_mps2[1] + change_mps2[2] * change_mps2[2];
  if (!crash_level_only) return total2 >= config_.trigger_mps2 * config_.trigger_mps2;
  const float lateral2 = change_mps2[0] * change_mps2[0] + change_mps2[1] * change_mps2[1];
  return total2 > config_.crash_peak_mps2 * config_.crash_peak_mps2 ||
         lateral2 > config_.crash_lateral_mps2 * config_.crash_lateral_mps2;
}

float ImpactDetector::add(Accumulator& acc, const Sample& s) const {
  const Vec3 d = minus(s.residual_mps2, reference_.residual_mps2);
  const float m = norm(d);
  if (m > acc.peak_mps2) {
    acc.before_peak_mps2 = acc.last_mps2;
    acc.peak_mps2 = m;
    acc.peak_z_mps2 = d[2];
    acc.has_after = false;
  } else if (!acc.has_after) {
    acc.after_peak_mps2 = m;
    acc.has_after = true;
  }
  const float lateral = std::sqrt(d[0] * d[0] + d[1] * d[1]);
  if (lateral > acc.lateral_max_mps2) acc.lateral_max_mps2 = lateral;
  const float rate_change = norm(minus(s.gyro_radps, reference_.gyro_radps));
  if (rate_change > acc.rate_change_max_radps) acc.rate_change_max_radps = rate_change;
  acc.last_mps2 = m;
  return m;
}

bool ImpactDetector::crash_seen(const Accumulator& acc, float peak_mps2) const {
  return peak_mps2 > config_.crash_peak_mps2 || acc.lateral_max_mps2 > config_.crash_lateral_mps2 ||
         acc.rate_change_max_radps > config_.crash_rate_radps;
}

ImpactClass ImpactDetector::classify(const Accumulator& acc, float peak_mps2) const {
  if (crash_seen(acc, peak_mps2)) return ImpactClass::crash;
  // The pole pushes the plate down the body z-axis; the floor or an obstacle pushes any other way.
  const bool downward = -acc.peak_z_mps2 >= config_.catch_axis_fraction * acc.peak_mps2;
  if (downward && catch_expected_) return ImpactClass::catch_impact;
  return ImpactClass::unexpected_impact;
}

// The vertex of the parabola through the largest sample and its two neighbours. At 1 kHz a
// 3 ms half-sine is three samples wide, and its largest sample can be 13 % below the peak.
float ImpactDetector::refined_peak() const {
  const float a = acc_.before_peak_mps2;
  const float b = acc_.peak_mps2;
  if (!acc_.has_after) return b;
  const float c = acc_.after_peak_mps2;
  const float curvature = a - 2.0f * b + c;  // negative: b is the largest
  if (!(curvature < -1e-6f)) return b;
  const float p = clampf(0.5f * (a - c) / curvature, -0.5f, 0.5f);
  return b - 0.25f * (a - c) * p;
}

// 3. The event is confirmed: replay the samples since the reference (at most kHistory - 1) to
// find the rising edge and the peak so far.
void ImpactDetector::confirm(std::uint32_t now_us, ImpactEvent& out) {
  std::array<float, kHistory> change_mps2{};  // by age
  Accumulator acc{};
  std::size_t quiet_age = reference_age_;  // the latest sample inside the onset band
  for (std::size_t age = reference_age_; age-- > 0;) {
    change_mps2[age] = add(acc, history(age));
    if (change_mps2[age] < config_.onset_mps2) quiet_age = age;
  }
  // The rising edge begins with the sample after quiet_age (the latest sample is above the
  // trigger, so quiet_age >= 1). Extend the line through its first two samples back to zero,
  // no further back than the quiet sample; a single-sample edge starts half-way.
  const Sample& first = history(quiet_age - 1);
  const float span_us = static_cast<float>(pa::elapsed_us(first.t_us, history(quiet_age).t_us));
  float back_us = 0.5f * span_us;
  if (quiet_age >= 2) {
    const float v0 = change_mps2[quiet_age - 1];
    const float v1 = change_mps2[quiet_age - 2];
    const float step_us = static_cast<float>(pa::elapsed_us(history(quiet_age - 2).t_us, first.t_us));
    if (v1 > v0 && step_us > 0.0f) back_us = v0 * step_us / (v1 - v0);
  }
  back_us = clampf(back_us, 0.0f, span_us > 0.0f ? span_us : 0.0f);
  onset_us_ = first.t_us - static_cast<std::uint32_t>(back_us + 0.5f);

  acc_ = acc;
  detected_us_ = now_us;
  count_ = static_cast<std::uint8_t>(count_ + 1u);
  phase_ = Phase::active;
  out = ImpactEvent{onset_us_, acc_.peak_mps2, classify(acc_, acc_.peak_mps2), ImpactStage::detected, count_,
                    detected_us_};
}

void ImpactDetector::finish(bool contact_over, ImpactEvent& out) {
  const float peak_mps2 = refined_peak();
  out = ImpactEvent{onset_us_, peak_mps2, classify(acc_, peak_mps2), ImpactStage::classified, count_, detected_us_};
  phase_ = contact_over ? Phase::idle : Phase::tail;
  above_ = 0;
}

}  // namespace fw
