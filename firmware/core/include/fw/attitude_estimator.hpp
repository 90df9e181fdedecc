// On-board attitude estimate for the failsafe levelled hover.
//
// In normal flight the ground station closes the attitude loop on motion capture and sends body
// rates (paper, Sections II-A and VII); the vehicle itself only needs to know which way is up when
// that stream stops. This is a Mahony-style complementary filter: the gyro is integrated into a
// quaternion and a proportional correction turns the estimated up direction towards the measured
// specific force, which at rest or in hover is gravity's reaction (+g along inertial up).
//
// Conventions: the quaternion (w, x, y, z) rotates body vectors into the inertial frame, inertial
// z up (eq. (4)); body axes as in mixer.hpp (x forward, y left, z up).
//
// Limits, by design:
// - Yaw is unobservable from the accelerometer and only integrates the gyro.
// - The correction is skipped while |accel| is outside (1 +- kAccelGateFraction) g: throws,
//   catches and impacts. In sustained accelerated flight a multirotor's accelerometer reads its
//   thrust direction, so the estimate then leans towards "level"; the filter is meant for the
//   near-hover failsafe, not for tracking aggressive manoeuvres.
// - A gyro bias b leaves a steady tilt error of about |b| / accel_gain_per_s (there is no bias
//   integrator, so accelerated flight cannot corrupt a bias estimate); calibrate the gyro at rest.
#pragma once

#include <cmath>

#include "fw/types.hpp"

namespace fw {

class AttitudeEstimator {
 public:
  static constexpr float kAccelGateFraction = 0.2f;  // correct only when ||a| - g| <= 0.2 g
  static constexpr float kDtMax_s = 0.02f;           // dt is clamped into [0, kDtMax_s]
  static constexpr float kGyroLimit_radps = 40.0f;   // gyro clamped per axis (2000 deg/s range)

  // accel_gain_per_s: bandwidth of the tilt correction. A non-finite or negative gain is
  // replaced by zero (pure gyro integration).
  explicit AttitudeEstimator(float accel_gain_per_s = 2.0f);

  // The tilt correction's bandwidth, changed at run time (the vehicle uses it on the ground
  // only: in flight the accelerometer reads the thrust direction, not gravity). A non-finite
  // or negative gain is replaced by zero.
  void set_accel_gain(float accel_gain_per_s) {
    accel_gain_per_s_ = std::isfinite(accel_gain_per_s) && accel_gain_per_s > 0.0f ? accel_gain_per_s : 0.0f;
  }

  // Back to level, and align again to the next usable accelerometer sample.
  void reset_level();

  // Removes a tilt error known from elsewhere: `true_up` is where inertial up truly lies,
  // expressed in the estimated inertial frame (near +z); the estimated frame is turned so that
  // it becomes +z, yaw unchanged to first order. A vector that is not finite or points down
  // changes nothing.
  void correct_tilt(const Vec3f& true_up);

  // One IMU sample. gyro_radps: body rates; accel_mps2: specific force in the body frame.
  // The first sample with a finite accelerometer inside the gate aligns the tilt to it (zero
  // yaw) instead of integrating; until then the gyro is integrated from level.
  // A non-finite gyro or dt rejects the whole sample; a non-finite accelerometer only skips
  // the correction.
  void update(const Vec3f& gyro_radps, const Vec3f& accel_mps2, float dt_s);

  const Quaternion& quaternion() const { return q_; }

  // Unit inertial-up vector expressed in the body frame: the third row of the body-to-inertial
  // rotation matrix of q. (Inline: the failsafe reads it every tick.)
  Vec3f up_in_body() const {
    const float w = q_[0], x = q_[1], y = q_[2], z = q_[3];
    return {2.0f * (x * z - w * y), 2.0f * (y * z + w * x), 1.0f - 2.0f * (x * x + y * y)};
  }

  // Cosine of the tilt: the body z-axis' component along inertial up (1 level, -1 inverted).
  float tilt_cos() const { return 1.0f - 2.0f * (q_[1] * q_[1] + q_[2] * q_[2]); }

  // A body vector in the estimated inertial frame.
  Vec3f to_inertial(const Vec3f& v) const { return rotate_to_inertial(q_, v); }
  static Vec3f rotate_to_inertial(const Quaternion& q, const Vec3f& v) {
    const float w = q[0], x = q[1], y = q[2], z = q[3];
    // v + 2 w (r x v) + 2 r x (r x v), r = (x, y, z)
    const float cx = y * v[2] - z * v[1], cy = z * v[0] - x * v[2], cz = x * v[1] - y * v[0];
    return {v[0] + 2.0f * (w * cx + y * cz - z * cy), v[1] + 2.0f * (w * cy + z * cx - x * cz),
            v[2] + 2.0f * (w * cz + x * cy - y * cx)};
  }

  // True once aligned to an accelerometer sample.
  bool aligned() const { return aligned_; }

 private:
  float accel_gain_per_s_ = 0.0f;
  Quaternion q_{1.0f, 0.0f, 0.0f, 0.0f};
  bool aligned_ = false;
};

}  // namespace fw
