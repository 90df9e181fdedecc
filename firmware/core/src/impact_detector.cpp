#include "fw/impact_detector.hpp"

#include <cmath>

#include "fw/float_ops.hpp"
#include "pa/sequence.hpp"

namespace fw {

using pa::proto::ImpactClass;

namespace {

[[gnu::always_inline]] inline Vec3f minus(const Vec3f& a, const Vec3f& b) {
  return Vec3f{a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}

[[gnu::always_inline]] inline float norm(const Vec3f& v) {
  return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

std::uint8_t clamp_u8(std::uint8_t v, std::uint8_t lo, std::uint8_t hi) {
  return v < lo ? lo : (v > hi ? hi : v);
}

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

static_assert(ImpactDetector::kMaxReferenceDelay < ImpactDetector::kHistory,
              "the history must hold the reference");

ImpactDetector::ImpactDetector(const ImpactDetectorConfig& config, const AirframeConfig& airframe)
    : config_(sanitised(config)),
      motor_time_constant_s_(airframe.motor_time_constant_s > 0.0f ? airframe.motor_time_constant_s : 0.0f),
      trigger2_(config_.trigger_mps2 * config_.trigger_mps2),
      crash_peak2_(config_.crash_peak_mps2 * config_.crash_peak_mps2),
      crash_lateral2_(config_.crash_lateral_mps2 * config_.crash_lateral_mps2) {}

void ImpactDetector::reset() {
  started_ = false;
  expected_mps2_ = 0.0f;
  history_ = {};
  newest_ = 0;
  filled_ = 0;
  phase_ = Phase::idle;
  reference_ = {};
  edge_ = {};
  above_ = 0;
  crash_level_only_ = false;
  catch_expected_ = false;
  landing_expected_ = false;
  acc_ = {};
  onset_us_ = 0;
  detected_us_ = 0;
  has_last_event_ = false;
  last_event_end_us_ = 0;
  has_settled_ = false;
  settled_us_ = 0;
}

Vec3f ImpactDetector::residual_mps2() const { return filled_ == 0 ? Vec3f{} : history(0).residual_mps2; }

[[gnu::always_inline]] inline const ImpactDetector::Sample& ImpactDetector::history(
    std::size_t samples_ago) const {
  return history_[(newest_ + kHistory - samples_ago) % kHistory];
}

bool ImpactDetector::update(const ImpactInput& in, ImpactEvent& out) {
  const float marker = nonfinite_marker(in.accel_mps2) + nonfinite_marker(in.gyro_radps) +
                       nonfinite_marker(in.commanded_thrust_mps2);
  if (!(marker == 0.0f)) return false;
  // A fixed-pitch rotor cannot pull down: a negative command means zero thrust.
  const float command_mps2 = in.commanded_thrust_mps2 > 0.0f ? in.commanded_thrust_mps2 : 0.0f;

  // 1. The thrust the motors produce now: the command through the first-order lag. The step
  //    uses 1 - exp(-x) ~ x / (1 + x/2) (no expf in the 1 kHz path), within 0.1 % for x <= 0.1.
  if (!started_) {
    expected_mps2_ = command_mps2;  // assume the motors had settled
    started_ = true;
  } else {
    // The step's gain depends on the sample interval only, which is nearly always the last one.
    const std::int32_t step_us = pa::elapsed_us(in.t_us, last_t_us_);
    if (!has_lag_gain_ || step_us != lag_gain_step_us_) {
      const float dt_s = clampf(static_cast<float>(step_us) * 1e-6f, config_.dt_min_s, config_.dt_max_s);
      float alpha = 1.0f;
      if (motor_time_constant_s_ > 0.0f) {
        const float x = dt_s / motor_time_constant_s_;
        alpha = x / (1.0f + 0.5f * x);
        if (alpha > 1.0f) alpha = 1.0f;
      }
      lag_gain_ = alpha;
      lag_gain_step_us_ = step_us;
      has_lag_gain_ = true;
    }
    expected_mps2_ += lag_gain_ * (command_mps2 - expected_mps2_);
  }
  last_t_us_ = in.t_us;

  newest_ = (newest_ + 1) % kHistory;
  Sample& s = history_[newest_];
  s.t_us = in.t_us;
  s.residual_mps2 = Vec3f{in.accel_mps2[0], in.accel_mps2[1], in.accel_mps2[2] - expected_mps2_};
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
      begin_event(delay);
      above_ = 1;
      crash_level_only_ = refractory;
      catch_expected_ = in.catch_expected;
      landing_expected_ = in.landing_expected;
      phase_ = Phase::pending;
      break;
    }
    case Phase::pending:
      catch_expected_ = catch_expected_ || in.catch_expected;
      landing_expected_ = landing_expected_ || in.landing_expected;
      if (!triggered(minus(s.residual_mps2, reference_.residual_mps2), crash_level_only_)) {
        phase_ = Phase::idle;  // a spike too short to confirm
        has_settled_ = true;
        settled_us_ = in.t_us;
        return false;
      }
      ++above_;
      accumulate(0, reference_, acc_, edge_);
      break;
    case Phase::active:
    case Phase::tail: {
      catch_expected_ = catch_expected_ || in.catch_expected;
      landing_expected_ = landing_expected_ || in.landing_expected;
      const float change_mps2 = add(acc_, s, reference_);
      const bool released = change_mps2 < config_.release_mps2;
      const bool expired =
          pa::elapsed_us(in.t_us, onset_us_) >= static_cast<std::int32_t>(config_.event_window_us);
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

[[gnu::always_inline]] inline bool ImpactDetector::triggered(const Vec3f& change_mps2,
                                                             bool crash_level_only) const {
  const float total2 =
      change_mps2[0] * change_mps2[0] + change_mps2[1] * change_mps2[1] + change_mps2[2] * change_mps2[2];
  if (!crash_level_only) return total2 >= trigger2_;
  const float lateral2 = change_mps2[0] * change_mps2[0] + change_mps2[1] * change_mps2[1];
  return total2 > crash_peak2_ || lateral2 > crash_lateral2_;
}

[[gnu::always_inline]] inline float ImpactDetector::add(Accumulator& acc, const Sample& s,
                                                        const Sample& reference) {
  const Vec3f d = minus(s.residual_mps2, reference.residual_mps2);
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
  const float rate_change = norm(minus(s.gyro_radps, reference.gyro_radps));
  if (rate_change > acc.rate_change_max_radps) acc.rate_change_max_radps = rate_change;
  acc.last_mps2 = m;
  return m;
}

// 3./4. The samples since the reference, oldest first, measured against it as they come (here
// the ones up to the triggering sample, then one per pending sample), so that no sample has to
// replay the whole rise. Out of line: the idle path that calls it keeps its registers, and the
// copies here stay in registers.
[[gnu::noinline]] void ImpactDetector::begin_event(std::size_t delay) {
  const Sample& reference = history(delay);
  reference_ = reference;
  Accumulator acc{};
  RisingEdge edge{};
  edge.quiet_us = reference.t_us;
  accumulate(delay - 1, reference, acc, edge);
  acc_ = acc;
  edge_ = edge;
}

[[gnu::always_inline]] inline void ImpactDetector::accumulate(std::size_t oldest_age, const Sample& reference,
                                                              Accumulator& acc, RisingEdge& edge) const {
  for (std::size_t age = oldest_age + 1; age-- > 0;) {
    const Sample& s = history(age);
    const float change_mps2 = add(acc, s, reference);
    if (change_mps2 < config_.onset_mps2) {
      edge.quiet_us = s.t_us;  // still inside the onset band: the edge has not begun
      edge.count = 0;
    } else if (edge.count == 0) {
      edge.first_us = s.t_us;
      edge.first_mps2 = change_mps2;
      edge.count = 1;
    } else if (edge.count == 1) {
      edge.second_us = s.t_us;
      edge.second_mps2 = change_mps2;
      edge.count = 2;
    }
  }
}

bool ImpactDetector::touchdown(const Accumulator& acc) const {
  return landing_expected_ && acc.peak_z_mps2 >= config_.catch_axis_fraction * acc.peak_mps2;
}

bool ImpactDetector::downward(const Accumulator& acc) const {
  return -acc.peak_z_mps2 >= config_.catch_axis_fraction * acc.peak_mps2;
}

bool ImpactDetector::crash_seen(const Accumulator& acc, float peak_mps2) const {
  // Touching down pushes up the body z-axis, as hard as the feet are stiff, and sideways as
  // hard as the floor's friction holds feet that still drift: only its peak against the
  // touchdown threshold and a tipping spin make it a crash.
  if (touchdown(acc))
    return peak_mps2 > config_.touchdown_crash_peak_mps2 ||
           acc.rate_change_max_radps > config_.crash_rate_radps;
  // Likewise a pole caught askew: it pushes the plate down and, through the plate's friction
  // (0.5-0.7), sideways by up to 0.7 of that. Its lateral part alone made a crash, and the
  // motors were cut at the catching height (a pole met at 50-60 degrees of tilt, peak 51 m/s^2:
  // hil campaign --plant hil/config/envelope.yaml --replay 29). In a catch window a push
  // mainly down the body z-axis is a crash only by its peak or a tipping spin.
  if (catch_expected_ && downward(acc))
    return peak_mps2 > config_.crash_peak_mps2 || acc.rate_change_max_radps > config_.crash_rate_radps;
  return peak_mps2 > config_.crash_peak_mps2 || acc.lateral_max_mps2 > config_.crash_lateral_mps2 ||
         acc.rate_change_max_radps > config_.crash_rate_radps;
}

ImpactClass ImpactDetector::classify(const Accumulator& acc, float peak_mps2) const {
  if (crash_seen(acc, peak_mps2)) return ImpactClass::crash;
  // The pole pushes the plate down the body z-axis; the floor or an obstacle pushes any other way.
  if (downward(acc) && catch_expected_) return ImpactClass::catch_impact;
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

// 3. The event is confirmed: the rising edge begins with the first sample after the latest one
// inside the onset band (the latest sample is above the trigger, so there is one). Extend the
// line through its first two samples back to zero, no further back than the quiet sample; a
// single-sample edge starts half-way.
void ImpactDetector::confirm(std::uint32_t now_us, ImpactEvent& out) {
  // Only a configuration whose crash levels lie below onset_mps2 can confirm with the latest
  // sample inside the band; the edge is then that sample.
  const std::uint32_t first_us = edge_.count > 0 ? edge_.first_us : now_us;
  const float span_us = edge_.count > 0 ? static_cast<float>(pa::elapsed_us(first_us, edge_.quiet_us)) : 0.0f;
  float back_us = 0.5f * span_us;
  if (edge_.count >= 2) {
    const float v0 = edge_.first_mps2;
    const float v1 = edge_.second_mps2;
    const float step_us = static_cast<float>(pa::elapsed_us(edge_.second_us, first_us));
    if (v1 > v0 && step_us > 0.0f) back_us = v0 * step_us / (v1 - v0);
  }
  back_us = clampf(back_us, 0.0f, span_us > 0.0f ? span_us : 0.0f);
  onset_us_ = first_us - static_cast<std::uint32_t>(back_us + 0.5f);

  detected_us_ = now_us;
  count_ = static_cast<std::uint8_t>(count_ + 1u);
  phase_ = Phase::active;
  out = ImpactEvent{onset_us_, acc_.peak_mps2, classify(acc_, acc_.peak_mps2), ImpactStage::detected,
                    count_,    detected_us_};
  out.touchdown = touchdown(acc_) && out.classification != ImpactClass::crash;
}

void ImpactDetector::finish(bool contact_over, ImpactEvent& out) {
  const float peak_mps2 = refined_peak();
  out = ImpactEvent{onset_us_, peak_mps2,   classify(acc_, peak_mps2), ImpactStage::classified,
                    count_,    detected_us_};
  out.touchdown = touchdown(acc_) && out.classification != ImpactClass::crash;
  phase_ = contact_over ? Phase::idle : Phase::tail;
  above_ = 0;
}

}  // namespace fw
