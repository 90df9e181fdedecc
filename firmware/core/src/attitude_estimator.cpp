#include "fw/attitude_estimator.hpp"

#include <cmath>
#include <limits>

#include "fw/float_ops.hpp"
#include "pa/constants.hpp"

namespace fw {
namespace {

// Normalises q in place; returns false (leaving q alone) if it cannot.
[[gnu::always_inline]] inline bool normalise(Quaternion& q) {
  const float n2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
  // Near 1 (as after every step) it is certainly normalisable; otherwise check (NaN fails both).
  if (!(std::fabs(n2 - 1.0f) <= 0.5f) && !(n2 >= 1.0e-12f && n2 <= std::numeric_limits<float>::max()))
    return false;
  const float inv = 1.0f / std::sqrt(n2);
  q = {q[0] * inv, q[1] * inv, q[2] * inv, q[3] * inv};
  return true;
}

}  // namespace

AttitudeEstimator::AttitudeEstimator(float accel_gain_per_s)
    : accel_gain_per_s_(std::isfinite(accel_gain_per_s) && accel_gain_per_s > 0.0f ? accel_gain_per_s
                                                                                   : 0.0f) {}

void AttitudeEstimator::reset_level() {
  q_ = {1.0f, 0.0f, 0.0f, 0.0f};
  aligned_ = false;
}

void AttitudeEstimator::correct_tilt(const Vec3f& true_up) {
  const float n2 = true_up[0] * true_up[0] + true_up[1] * true_up[1] + true_up[2] * true_up[2];
  if (!(n2 > 0.0f) || !(true_up[2] > 0.0f) || !std::isfinite(n2)) return;
  const float inv = 1.0f / std::sqrt(n2);
  // The shortest rotation taking u onto +z, (1 + u.z, u x z), applied on the inertial side.
  Quaternion d{1.0f + true_up[2] * inv, true_up[1] * inv, -true_up[0] * inv, 0.0f};
  if (!normalise(d)) return;
  const float w = q_[0], x = q_[1], y = q_[2], z = q_[3];
  Quaternion q{d[0] * w - d[1] * x - d[2] * y, d[0] * x + d[1] * w + d[2] * z, d[0] * y - d[1] * z + d[2] * w,
               d[0] * z + d[1] * y - d[2] * x};
  if (normalise(q)) q_ = q;
}

void AttitudeEstimator::update(const Vec3f& gyro_radps, const Vec3f& accel_mps2, float dt_s) {
  if (!(nonfinite_marker(gyro_radps) + nonfinite_marker(dt_s) == 0.0f)) return;
  const float dt_clamped_s = clampf(dt_s, 0.0f, kDtMax_s);

  // Is the accelerometer a usable gravity reference on this sample? It is needed only to align
  // and while the correction has a gain (the vehicle sets none in flight), and a zero gain
  // would add nothing below.
  bool accel_usable = false;
  Vec3f up_meas{};
  if (!aligned_ || accel_gain_per_s_ > 0.0f) {
    const float n2 =
        accel_mps2[0] * accel_mps2[0] + accel_mps2[1] * accel_mps2[1] + accel_mps2[2] * accel_mps2[2];
    const float lo = (1.0f - kAccelGateFraction) * pa::kGravityFloat_mps2;
    const float hi = (1.0f + kAccelGateFraction) * pa::kGravityFloat_mps2;
    // A non-finite component makes n2 NaN or infinite, which fails the upper bound.
    if (n2 >= lo * lo && n2 <= hi * hi) {
      const float inv = 1.0f / std::sqrt(n2);
      up_meas = {accel_mps2[0] * inv, accel_mps2[1] * inv, accel_mps2[2] * inv};
      accel_usable = true;
    }
  }

  if (!aligned_ && accel_usable) {
    // Shortest rotation taking the measured up (body) onto inertial z: q = (1 + u.z, u x z).
    Quaternion q{1.0f + up_meas[2], up_meas[1], -up_meas[0], 0.0f};
    if (q[0] < 1.0e-6f) q = {0.0f, 1.0f, 0.0f, 0.0f};  // upside down: half a turn about x
    if (normalise(q)) {
      q_ = q;
      aligned_ = true;
    }
    return;
  }

  Vec3f omega_radps = gyro_radps;
  if (!all_within(omega_radps, kGyroLimit_radps)) {  // inside the range (as usual) the clamp changes nothing
    for (float& w : omega_radps) w = clampf(w, -kGyroLimit_radps, kGyroLimit_radps);
  }
  if (accel_usable) {
    // Rotating the body at k (u_meas x u_est) moves the estimated up towards the measured one
    // at rate k sin(angle): d/dt u_est = u_est x omega for a fixed inertial vector. The sample's
    // accelerometer belongs to the end of this step, so it is compared with the estimate
    // predicted over the step (to first order); comparing it with the start of the step would
    // leave a steady lead of omega dt while rotating.
    const Vec3f up_prev = up_in_body();
    const float g0 = omega_radps[0] * dt_clamped_s;
    const float g1 = omega_radps[1] * dt_clamped_s;
    const float g2 = omega_radps[2] * dt_clamped_s;
    const Vec3f up_est{up_prev[0] + (up_prev[1] * g2 - up_prev[2] * g1),
                       up_prev[1] + (up_prev[2] * g0 - up_prev[0] * g2),
                       up_prev[2] + (up_prev[0] * g1 - up_prev[1] * g0)};
    const float k = accel_gain_per_s_;
    omega_radps[0] += k * (up_meas[1] * up_est[2] - up_meas[2] * up_est[1]);
    omega_radps[1] += k * (up_meas[2] * up_est[0] - up_meas[0] * up_est[2]);
    omega_radps[2] += k * (up_meas[0] * up_est[1] - up_meas[1] * up_est[0]);
  }

  // q <- q (x) dq with dq the rotation by omega dt, from the series of cos and sin of half the
  // angle to second order (no trig), then renormalised.
  const float half_dt_s = 0.5f * dt_clamped_s;
  const float hx = omega_radps[0] * half_dt_s;
  const float hy = omega_radps[1] * half_dt_s;
  const float hz = omega_radps[2] * half_dt_s;
  const float h2 = hx * hx + hy * hy + hz * hz;
  const float dw = 1.0f - 0.5f * h2;
  const float s = 1.0f - h2 * (1.0f / 6.0f);
  const float dx = s * hx, dy = s * hy, dz = s * hz;
  const float w = q_[0], x = q_[1], y = q_[2], z = q_[3];
  Quaternion q{w * dw - x * dx - y * dy - z * dz, w * dx + x * dw + y * dz - z * dy,
               w * dy - x * dz + y * dw + z * dx, w * dz + x * dy - y * dx + z * dw};
  if (normalise(q)) q_ = q;
}

}  // namespace fw
