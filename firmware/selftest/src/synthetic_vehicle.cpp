#include "fw/synthetic_vehicle.hpp"

#include <cmath>

namespace fw::selftest {

namespace {
constexpr float kFloorStiffness_Npm = 2000.0f;
constexpr float kFloorDamping_Nspm = 40.0f;

// v rotated by q (body to inertial) and by its inverse.
Vec3f rotate(const Quaternion& q, const Vec3f& v) {
  const float w = q[0], x = q[1], y = q[2], z = q[3];
  return Vec3f{(1 - 2 * (y * y + z * z)) * v[0] + 2 * (x * y - w * z) * v[1] + 2 * (x * z + w * y) * v[2],
               2 * (x * y + w * z) * v[0] + (1 - 2 * (x * x + z * z)) * v[1] + 2 * (y * z - w * x) * v[2],
               2 * (x * z - w * y) * v[0] + 2 * (y * z + w * x) * v[1] + (1 - 2 * (x * x + y * y)) * v[2]};
}
Vec3f rotate_inverse(const Quaternion& q, const Vec3f& v) {
  return rotate(Quaternion{q[0], -q[1], -q[2], -q[3]}, v);
}
}  // namespace

SyntheticVehicle::SyntheticVehicle(const AirframeConfig& airframe)
    : airframe_(airframe), geometry_(airframe) {
  p_[2] = -airframe.mass_kg * pa::kGravityFloat_mps2 / kFloorStiffness_Npm;  // at rest on its legs
}

float SyntheticVehicle::noise() {
  rng_ = rng_ * 1664525u + 1013904223u;  // LCG: reproducible on every target
  return static_cast<float>(rng_ >> 8) / 16777216.0f - 0.5f;
}

void SyntheticVehicle::step(const Motors& command, const Vec3f& external_force_N, float dt_s) {
  // Motors: first-order lag towards the commanded thrust.
  const float alpha = dt_s / (airframe_.motor_time_constant_s + dt_s);
  for (int i = 0; i < 4; ++i)
    thrust_N_[i] += alpha * (command[i] * airframe_.motor_thrust_max_N - thrust_N_[i]);
  const MixerInput effect = geometry_.effect(thrust_N_);

  // Rotation: J w' = tau - w x J w, then the quaternion kinematics q' = q (0, w) / 2.
  const float* J = airframe_.inertia_kgm2;
  const Vec3f Jw{J[0] * w_[0], J[1] * w_[1], J[2] * w_[2]};
  const Vec3f gyroscopic{w_[1] * Jw[2] - w_[2] * Jw[1], w_[2] * Jw[0] - w_[0] * Jw[2],
                         w_[0] * Jw[1] - w_[1] * Jw[0]};
  const float m = airframe_.mass_kg;
  if (!on_floor_) {
    for (int i = 0; i < 3; ++i)
      w_[i] += dt_s * (effect.torque_Nm[i] + disturbance_Nm_[i] - gyroscopic[i]) / J[i];
  } else {
    w_ = Vec3f{};  // standing on its legs
  }
  const Quaternion q = q_;
  q_[0] += 0.5f * dt_s * (-q[1] * w_[0] - q[2] * w_[1] - q[3] * w_[2]);
  q_[1] += 0.5f * dt_s * (q[0] * w_[0] + q[2] * w_[2] - q[3] * w_[1]);
  q_[2] += 0.5f * dt_s * (q[0] * w_[1] - q[1] * w_[2] + q[3] * w_[0]);
  q_[3] += 0.5f * dt_s * (q[0] * w_[2] + q[1] * w_[1] - q[2] * w_[0]);
  const float n = std::sqrt(q_[0] * q_[0] + q_[1] * q_[1] + q_[2] * q_[2] + q_[3] * q_[3]);
  for (float& c : q_) c /= n;

  // Translation: thrust along body z, the external force, gravity, and the floor at z = 0.
  const Vec3f thrust_inertial = rotate(q_, Vec3f{0, 0, effect.thrust_N});
  Vec3f force{thrust_inertial[0] + external_force_N[0], thrust_inertial[1] + external_force_N[1],
              thrust_inertial[2] + external_force_N[2] - m * pa::kGravityFloat_mps2};
  // The floor: stiff, well-damped landing gear (about 60 rad/s), so a touchdown is felt as a
  // deceleration of a few g over some tens of ms, as a real IMU feels it.
  Vec3f floor_force{};
  on_floor_ = p_[2] <= 0;
  if (on_floor_) {
    floor_force[2] = -kFloorStiffness_Npm * p_[2] - kFloorDamping_Nspm * v_[2];
    if (floor_force[2] < 0) floor_force[2] = 0;  // the floor pushes, never pulls
    force[2] += floor_force[2];
    force[0] -= kFloorDamping_Nspm * v_[0];  // friction on the legs
    force[1] -= kFloorDamping_Nspm * v_[1];
  }
  for (int i = 0; i < 3; ++i) {
    v_[i] += dt_s * force[i] / m;
    p_[i] += dt_s * v_[i];
  }
  // What the accelerometer feels: every force but gravity, in the body frame.
  const Vec3f felt{thrust_inertial[0] + external_force_N[0] + floor_force[0],
                   thrust_inertial[1] + external_force_N[1] + floor_force[1],
                   thrust_inertial[2] + external_force_N[2] + floor_force[2]};
  const Vec3f felt_body = rotate_inverse(q_, felt);
  for (int i = 0; i < 3; ++i) specific_force_body_[i] = felt_body[i] / m;
}

ImuSample SyntheticVehicle::imu(std::uint32_t t_us) {
  ImuSample s;
  s.t_us = t_us;
  for (int i = 0; i < 3; ++i) {
    s.gyro_radps[i] = w_[i] + 0.004f * noise();
    s.accel_mps2[i] = specific_force_body_[i] + 0.05f * noise();
  }
  return s;
}

float SyntheticVehicle::tilt_cos() const { return rotate(q_, Vec3f{0, 0, 1})[2]; }

Vec3f SyntheticVehicle::up_in_body() const { return rotate_inverse(q_, Vec3f{0, 0, 1}); }

}  // namespace fw::selftest
