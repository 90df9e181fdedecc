#include "fw/mixer.hpp"

#include <cmath>

#include "fw/float_ops.hpp"

namespace fw {
namespace {

constexpr float kInvSqrt2 = 0.70710678f;

bool finite(const MixerInput& in) {
  return std::isfinite(in.thrust_N) && std::isfinite(in.torque_Nm[0]) && std::isfinite(in.torque_Nm[1]) &&
         std::isfinite(in.torque_Nm[2]);
}

// Every value inside the limit, and therefore finite (a NaN or an infinity makes the sum fail the
// comparison). Conservative: a request whose values are each inside but whose sum is not takes
// the general path, where the clip then changes nothing.
[[gnu::always_inline]] inline bool within_request_limit(const MixerInput& in) {
  const float sum = std::fabs(in.thrust_N) + std::fabs(in.torque_Nm[0]) + std::fabs(in.torque_Nm[1]) +
                    std::fabs(in.torque_Nm[2]);
  return sum <= Mixer::kRequestLimit;
}

// Lowers `fraction` (the share of the yaw differential applied) so that motor_N + fraction *
// diff_N stays inside [lo_N, hi_N], for a non-zero diff_N.
// The collective and torques of the motor thrusts: the sums over the sign tables, motor by
// motor from zero (the equations in mixer.hpp).
[[gnu::always_inline]] inline MixerInput wrench(const Motors& thrust_N, float half_span_m,
                                                float yaw_moment_m) {
  const float f0 = thrust_N[0], f1 = thrust_N[1], f2 = thrust_N[2], f3 = thrust_N[3];
  const float roll = 0.0f - f0 + f1 + f2 - f3;
  const float pitch = 0.0f - f0 + f1 - f2 + f3;
  const float yaw = 0.0f - f0 - f1 + f2 + f3;
  return MixerInput{0.0f + f0 + f1 + f2 + f3, {half_span_m * roll, half_span_m * pitch, yaw_moment_m * yaw}};
}

[[gnu::always_inline]] inline void fit_yaw(float motor_N, float diff_N, float lo_N, float hi_N,
                                           float& fraction) {
  if (diff_N > 0.0f) {
    const float room_N = hi_N - motor_N;
    if (room_N < fraction * diff_N) fraction = room_N / diff_N;
  } else {
    const float room_N = lo_N - motor_N;
    if (room_N > fraction * diff_N) fraction = room_N / diff_N;
  }
}

}  // namespace

Mixer::Mixer(const AirframeConfig& airframe) {
  const float arm_m = airframe.arm_length_m;
  const float k_m = airframe.yaw_moment_per_thrust_m;
  const float lo_N = airframe.motor_thrust_min_N;
  const float hi_N = airframe.motor_thrust_max_N;
  valid_ = std::isfinite(arm_m) && std::isfinite(k_m) && std::isfinite(lo_N) && std::isfinite(hi_N) &&
           arm_m > 0.0f && k_m > 0.0f && lo_N >= 0.0f && lo_N < hi_N;
  if (!valid_) return;
  half_span_m_ = arm_m * kInvSqrt2;
  yaw_moment_m_ = k_m;
  inv_4a_per_m_ = 1.0f / (4.0f * half_span_m_);
  inv_4k_per_m_ = 1.0f / (4.0f * yaw_moment_m_);
  thrust_min_N_ = lo_N;
  thrust_max_N_ = hi_N;
  thrust_ceiling_N_ = hi_N;
}

bool Mixer::set_command_factor(float factor) {
  if (!valid_ || !std::isfinite(factor) || !(factor > 0.0f)) return false;
  const float ceiling_N = thrust_max_N_ / factor;
  if (!(ceiling_N > thrust_min_N_) || !std::isfinite(ceiling_N)) return false;
  thrust_ceiling_N_ = ceiling_N;
  return true;
}

MixerOutput Mixer::rejected(float motor_thrust_N) const {
  MixerOutput out;
  for (int i = 0; i < 4; ++i) {
    out.thrust_N[i] = motor_thrust_N;
    out.command[i] = valid_ ? motor_thrust_N / thrust_ceiling_N_ : 0.0f;
  }
  out.saturation = 0xFFu;
  return out;
}

MixerInput Mixer::effect(const Motors& thrust_N) const {
  return wrench(thrust_N, half_span_m_, yaw_moment_m_);
}

MixerOutput Mixer::mix(const MixerInput& input) const {
  if (!valid_) return rejected(0.0f);

  float collective_N = input.thrust_N;
  float roll_Nm = input.torque_Nm[0];
  float pitch_Nm = input.torque_Nm[1];
  float yaw_Nm = input.torque_Nm[2];
  // The common request is finite and inside the limit, where the clip changes nothing.
  if (!within_request_limit(input)) {
    if (!finite(input)) return rejected(thrust_min_N_);
    collective_N = clampf(collective_N, -kRequestLimit, kRequestLimit);
    roll_Nm = clampf(roll_Nm, -kRequestLimit, kRequestLimit);
    pitch_Nm = clampf(pitch_Nm, -kRequestLimit, kRequestLimit);
    yaw_Nm = clampf(yaw_Nm, -kRequestLimit, kRequestLimit);
  }

  const float lo_N = thrust_min_N_;
  const float hi_N = thrust_ceiling_N_;
  const float span_N = hi_N - lo_N;

  std::uint8_t flags = 0;

  // 1. Roll and pitch: the per-motor differential must fit the motors' span. If it does not,
  //    both axes are scaled by the same factor, which keeps the direction of the tilt torque
  //    (what a balancing or catching manoeuvre needs most) and gives up only its magnitude.
  //    With the sign tables the four differentials are (-s, +s, +d, -d) with
  //    s = (roll + pitch) / 4a and d = (roll - pitch) / 4a, so they span [-m, m] with
  //    m = max(|s|, |d|). (Each is summed in its own signs, as the tables do, so that even the
  //    sign of a zero is the tables'.)
  Motors rp_N{(-roll_Nm - pitch_Nm) * inv_4a_per_m_, (roll_Nm + pitch_Nm) * inv_4a_per_m_,
              (roll_Nm - pitch_Nm) * inv_4a_per_m_, (pitch_Nm - roll_Nm) * inv_4a_per_m_};
  float m_N = std::fabs(rp_N[1]) > std::fabs(rp_N[2]) ? std::fabs(rp_N[1]) : std::fabs(rp_N[2]);
  if (m_N + m_N > span_N) {
    const float scale = span_N / (m_N + m_N);
    for (float& v : rp_N) v *= scale;
    m_N *= scale;
    if (roll_Nm > 0.0f) flags |= saturation::roll_pos;
    if (roll_Nm < 0.0f) flags |= saturation::roll_neg;
    if (pitch_Nm > 0.0f) flags |= saturation::pitch_pos;
    if (pitch_Nm < 0.0f) flags |= saturation::pitch_neg;
  }

  // 2. Collective: shift the common per-motor thrust into the band where the roll/pitch
  //    differential stays inside [min, max]. After step 1 the band is never empty; when the
  //    differential fills the span exactly, rounding may invert it by an ulp, and it is then
  //    the single point between (the final clamp absorbs the ulp).
  float base_lo_N = lo_N + m_N;
  float base_hi_N = hi_N - m_N;
  if (base_hi_N < base_lo_N) base_lo_N = base_hi_N = 0.5f * (base_lo_N + base_hi_N);
  float base_N = 0.25f * collective_N;
  if (base_N > base_hi_N) {
    base_N = base_hi_N;
    flags |= saturation::collective_high;
  } else if (base_N < base_lo_N) {
    base_N = base_lo_N;
    flags |= saturation::collective_low;
  }

  // 3. Yaw: the largest fraction in [0, 1] of the yaw differential that keeps every motor in
  //    bounds. The yaw differential sums to zero, so it leaves the collective untouched.
  //    With kYawSign, motors 0 and 1 get -yaw_N and motors 2 and 3 +yaw_N.
  const Motors motor_N{base_N + rp_N[0], base_N + rp_N[1], base_N + rp_N[2], base_N + rp_N[3]};
  //    Usually all of it fits, which the extreme motor of each pair decides: motors 0 and 1 sit
  //    at base_N -+ |rp_N[1]|, motors 2 and 3 at base_N +- |rp_N[2]|, and rounding is monotonic,
  //    so these two comparisons decide exactly what fit_yaw() would for the four motors.
  const float yaw_N = yaw_Nm * inv_4k_per_m_;
  const float pair01_N = std::fabs(rp_N[1]);
  const float pair23_N = std::fabs(rp_N[2]);
  const bool yaw_fits = yaw_N > 0.0f
                            ? hi_N - (base_N + pair23_N) >= yaw_N && lo_N - (base_N - pair01_N) <= -yaw_N
                            : hi_N - (base_N + pair01_N) >= -yaw_N && lo_N - (base_N - pair23_N) <= yaw_N;
  float yaw_fraction = 1.0f;
  if (yaw_N != 0.0f && !yaw_fits) {
    fit_yaw(motor_N[0], -yaw_N, lo_N, hi_N, yaw_fraction);
    fit_yaw(motor_N[1], -yaw_N, lo_N, hi_N, yaw_fraction);
    fit_yaw(motor_N[2], yaw_N, lo_N, hi_N, yaw_fraction);
    fit_yaw(motor_N[3], yaw_N, lo_N, hi_N, yaw_fraction);
    yaw_fraction = clampf(yaw_fraction, 0.0f, 1.0f);
    if (yaw_fraction < 1.0f) flags |= yaw_N > 0.0f ? saturation::yaw_pos : saturation::yaw_neg;
  }

  const Motors thrust_N{clampf(motor_N[0] - yaw_fraction * yaw_N, lo_N, hi_N),
                        clampf(motor_N[1] - yaw_fraction * yaw_N, lo_N, hi_N),
                        clampf(motor_N[2] + yaw_fraction * yaw_N, lo_N, hi_N),
                        clampf(motor_N[3] + yaw_fraction * yaw_N, lo_N, hi_N)};

  // What was not allocated, measured on the motor thrusts actually commanded.
  const MixerInput achieved = wrench(thrust_N, half_span_m_, yaw_moment_m_);
  return MixerOutput{thrust_N,
                     {thrust_N[0] / hi_N, thrust_N[1] / hi_N, thrust_N[2] / hi_N, thrust_N[3] / hi_N},
                     flags,
                     {input.torque_Nm[0] - achieved.torque_Nm[0], input.torque_Nm[1] - achieved.torque_Nm[1],
                      input.torque_Nm[2] - achieved.torque_Nm[2]},
                     input.thrust_N - achieved.thrust_N};
}

}  // namespace fw
