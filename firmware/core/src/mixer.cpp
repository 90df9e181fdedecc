#include "fw/mixer.hpp"

#include <cmath>

namespace fw {
namespace {

constexpr float kInvSqrt2 = 0.70710678f;

float clampf(float v, float lo, float hi) { return v < lo ? lo : (v > hi ? hi : v); }

bool finite(const MixerInput& in) {
  return std::isfinite(in.thrust_N) && std::isfinite(in.torque_Nm[0]) &&
         std::isfinite(in.torque_Nm[1]) && std::isfinite(in.torque_Nm[2]);
}

}  // namespace

Mixer::Mixer(const AirframeConfig& airframe) {
  const float arm_m = airframe.arm_length_m;
  const float k_m = airframe.yaw_moment_per_thrust_m;
  const float lo_N = airframe.motor_thrust_min_N;
  const float hi_N = airframe.motor_thrust_max_N;
  valid_ = std::isfinite(arm_m) && std::isfinite(k_m) && std::isfinite(lo_N) &&
           std::isfinite(hi_N) && arm_m > 0.0f && k_m > 0.0f && lo_N >= 0.0f && lo_N < hi_N;
  if (!valid_) return;
  half_span_m_ = arm_m * kInvSqrt2;
  yaw_moment_m_ = k_m;
  inv_4a_per_m_ = 1.0f / (4.0f * half_span_m_);
  inv_4k_per_m_ = 1.0f / (4.0f * yaw_moment_m_);
  thrust_min_N_ = lo_N;
  thrust_max_N_ = hi_N;
}

MixerOutput Mixer::rejected(float motor_thrust_N) const {
  MixerOutput out;
  for (int i = 0; i < 4; ++i) {
    out.thrust_N[i] = motor_thrust_N;
    out.command[i] = valid_ ? motor_thrust_N / thrust_max_N_ : 0.0f;
  }
  out.saturation = 0xFFu;
  return out;
}

MixerInput Mixer::effect(const Motors& thrust_N) const {
  MixerInput e;
  float roll = 0.0f, pitch = 0.0f, yaw = 0.0f;
  for (int i = 0; i < 4; ++i) {
    e.thrust_N += thrust_N[i];
    roll += kRollSign[i] * thrust_N[i];
    pitch += kPitchSign[i] * thrust_N[i];
    yaw += kYawSign[i] * thrust_N[i];
  }
  e.torque_Nm = {half_span_m_ * roll, half_span_m_ * pitch, yaw_moment_m_ * yaw};
  return e;
}

MixerOutput Mixer::mix(const MixerInput& input) const {
  if (!valid_) return rejected(0.0f);
  if (!finite(input)) return rejected(thrust_min_N_);

  const float lo_N = thrust_min_N_;
  const float hi_N = thrust_max_N_;
  const float span_N = hi_N - lo_N;

  const float thrust_N = clampf(input.thrust_N, -kRequestLimit, kRequestLimit);
  const float roll_Nm = clampf(input.torque_Nm[0], -kRequestLimit, kRequestLimit);
  const float pitch_Nm = clampf(input.torque_Nm[1], -kRequestLimit, kRequestLimit);
  const float yaw_Nm = clampf(input.torque_Nm[2], -kRequestLimit, kRequestLimit);

  std::uint8_t flags = 0;

  // 1. Roll and pitch: the per-motor differential must fit the motors' span. If it does not,
  //    both axes are scaled by the same factor, which keeps the direction of the tilt torque
  //    (what a balancing or catching manoeuvre needs most) and gives up only its magnitude.
  Motors rp{};
  float rp_lo = 0.0f, rp_hi = 0.0f;
  for (int i = 0; i < 4; ++i) {
    rp[i] = (kRollSign[i] * roll_Nm + kPitchSign[i] * pitch_Nm) * inv_4a_per_m_;
    rp_lo = i == 0 ? rp[i] : (rp[i] < rp_lo ? rp[i] : rp_lo);
    rp_hi = i == 0 ? rp[i] : (rp[i] > rp_hi ? rp[i] : rp_hi);
  }
  const float rp_range = rp_hi - rp_lo;
  if (rp_range > span_N) {
    const float scale = span_N / rp_range;
    for (float& v : rp) v *= scale;
    rp_lo *= scale;
    rp_hi *= scale;
    if (roll_Nm > 0.0f) flags |= saturation::roll_pos;
    if (roll_Nm < 0.0f) flags |= saturation::roll_neg;
    if (pitch_Nm > 0.0f) flags |= saturation::pitch_pos;
    if (pitch_Nm < 0.0f) flags |= saturation::pitch_neg;
  }

  // 2. Collective: shift the common per-motor thrust into the band where the roll/pitch
  //    differential stays inside [min, max]. After step 1 the band is never empty; when the
  //    differential fills the span exactly, rounding may invert it by an ulp, and it is then
  //    the single point between (the final clamp absorbs the ulp).
  float base_lo_N = lo_N - rp_lo;
  float base_hi_N = hi_N - rp_hi;
  if (base_hi_N < base_lo_N) base_lo_N = base_hi_N = 0.5f * (base_lo_N + base_hi_N);
  float base_N = 0.25f * thrust_N;
  if (base_N > base_hi_N) {
    base_N = base_hi_N;
    flags |= saturation::collective_high;
  } else if (base_N < base_lo_N) {
    base_N = base_lo_N;
    flags |= saturation::collective_low;
  }

  // 3. Yaw: the largest fraction in [0, 1] of the yaw differential that keeps every motor in
  //    bounds. The yaw differential sums to zero, so it leaves the collective untouched.
  Motors motor_N{};
  Motors yaw_diff{};
  float yaw_fraction = 1.0f;
  for (int i = 0; i < 4; ++i) {
    motor_N[i] = base_N + rp[i];
    yaw_diff[i] = kYawSign[i] * yaw_Nm * inv_4k_per_m_;
    if (yaw_diff[i] > 0.0f) {
      const float room_N = hi_N - motor_N[i];
      if (room_N < yaw_fraction * yaw_diff[i]) yaw_fraction = room_N / yaw_diff[i];
    } else if (yaw_diff[i] < 0.0f) {
      const float room_N = lo_N - motor_N[i];
      if (room_N > yaw_fraction * yaw_diff[i]) yaw_fraction = room_N / yaw_diff[i];
    }
  }
  yaw_fraction = clampf(yaw_fraction, 0.0f, 1.0f);
  if (yaw_fraction < 1.0f) {
    if (yaw_Nm > 0.0f) flags |= saturation::yaw_pos;
    if (yaw_Nm < 0.0f) flags |= saturation::yaw_neg;
  }

  MixerOutput out;
  for (int i = 0; i < 4; ++i) {
    out.thrust_N[i] = clampf(motor_N[i] + yaw_fraction * yaw_diff[i], lo_N, hi_N);
    out.command[i] = out.thrust_N[i] / hi_N;
  }
  out.saturation = flags;

  // What was not allocated, measured on the motor thrusts actually commanded.
  const MixerInput achieved = effect(out.thrust_N);
  out.thrust_unallocated_N = input.thrust_N - achieved.thrust_N;
  for (int a = 0; a < 3; ++a) out.torque_unallocated_Nm[a] = input.torque_Nm[a] - achieved.torque_Nm[a];
  return out;
}

}  // namespace fw
