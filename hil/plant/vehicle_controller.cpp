#include "hil/plant/vehicle_controller.hpp"

#include <algorithm>
#include <cmath>

#include "hil/plant/motor.hpp"

namespace hil {

namespace {
Vec3 vee(const Mat3& m) { return Vec3(m(2, 1), m(0, 2), m(1, 0)); }
}  // namespace

VehicleController::VehicleController(const VehicleConfig& vehicle, double gravity_mps2,
                                     const VehicleControllerGains& gains)
    : vehicle_(vehicle), gravity_mps2_(gravity_mps2), gains_(gains) {
  // Each motor's share of collective thrust and torque, from the same geometry the plant uses.
  Eigen::Matrix4d effect;
  for (int i = 0; i < 4; ++i) {
    const Vec3 r = motor_position_body_m(vehicle, i);
    effect(0, i) = 1.0;
    effect(1, i) = r.y();
    effect(2, i) = -r.x();
    effect(3, i) = motor_yaw_sign(i) * vehicle.yaw_moment_per_thrust_m;
  }
  allocation_inverse_ = effect.inverse();
}

MotorCommands VehicleController::update(const VehicleState& truth, const VehicleSetpoint& sp, double dt_s) {
  const RigidBodyState& s = truth.body;
  const double m = vehicle_.mass_kg;

  // Desired acceleration.
  const double wp = gains_.position_radps;
  const double wz = gains_.height_radps;
  const Vec3 e_p = sp.position_m - s.position_m;
  const Vec3 e_v = sp.velocity_mps - s.velocity_mps;
  Vec3 a = sp.acceleration_mps2;
  if (sp.hold_horizontal) {
    a.head<2>() += wp * wp * e_p.head<2>() + 2.0 * gains_.position_damping * wp * e_v.head<2>();
  }
  const double ki = gains_.height_integral_per_s * wz * wz;
  if (std::isfinite(dt_s) && dt_s > 0.0) {
    height_integral_m_s_ = std::clamp(height_integral_m_s_ + e_p.z() * dt_s, -2.0 / ki, 2.0 / ki);
  }
  a.z() += wz * wz * e_p.z() + 2.0 * gains_.position_damping * wz * e_v.z() + ki * height_integral_m_s_;
  const double a_xy = a.head<2>().norm();
  if (a_xy > gains_.acceleration_max_mps2) a.head<2>() *= gains_.acceleration_max_mps2 / a_xy;

  // Desired thrust direction, tilt limited.
  Vec3 thrust = m * (a + Vec3(0.0, 0.0, gravity_mps2_));
  // Keep a little upward thrust so the direction is defined (and the attitude held).
  if (thrust.z() < 0.02 * m * gravity_mps2_) thrust.z() = 0.02 * m * gravity_mps2_;
  const double horizontal = thrust.head<2>().norm();
  const double horizontal_max = thrust.z() * std::tan(gains_.tilt_max_rad);
  if (horizontal > horizontal_max) thrust.head<2>() *= horizontal_max / horizontal;
  const Vec3 b3 = thrust.normalized();
  const Vec3 heading(std::cos(sp.yaw_rad), std::sin(sp.yaw_rad), 0.0);
  const Vec3 b2 = b3.cross(heading).normalized();
  const Vec3 b1 = b2.cross(b3);
  Mat3 r_d;
  r_d.col(0) = b1;
  r_d.col(1) = b2;
  r_d.col(2) = b3;

  // Collective thrust along the current body z-axis, and the attitude law.
  const Mat3 r = s.rotation();
  const double collective_N = std::max(0.0, thrust.dot(r.col(2)));
  const Vec3 e_r = 0.5 * vee(r_d.transpose() * r - r.transpose() * r_d);
  const Vec3 w = s.rate_body_radps;
  const Vec3 inertia(vehicle_.inertia_xx_kgm2, vehicle_.inertia_yy_kgm2, vehicle_.inertia_zz_kgm2);
  const double wa = gains_.attitude_radps;
  // Yaw is slow (rotor drag torque is small): half the bandwidth.
  const Vec3 kr(wa * wa, wa * wa, 0.25 * wa * wa);
  const Vec3 kw(2.0 * gains_.attitude_damping * wa, 2.0 * gains_.attitude_damping * wa,
                gains_.attitude_damping * wa);
  const Vec3 torque =
      inertia.cwiseProduct(-kr.cwiseProduct(e_r) - kw.cwiseProduct(w)) + w.cross(inertia.cwiseProduct(w));

  return motors(truth, Eigen::Vector4d(collective_N, torque.x(), torque.y(), torque.z()));
}

MotorCommands VehicleController::track_rates(const VehicleState& truth, double thrust_mps2,
                                             const Vec3& rates_body_radps) const {
  const Vec3 w = truth.body.rate_body_radps;
  const Vec3 inertia(vehicle_.inertia_xx_kgm2, vehicle_.inertia_yy_kgm2, vehicle_.inertia_zz_kgm2);
  const Vec3 k(gains_.rate_radps, gains_.rate_radps, gains_.rate_radps / 3.0);
  const Vec3 torque =
      inertia.cwiseProduct(k.cwiseProduct(rates_body_radps - w)) + w.cross(inertia.cwiseProduct(w));
  const double collective_N = std::max(0.0, vehicle_.mass_kg * thrust_mps2);
  return motors(truth, Eigen::Vector4d(collective_N, torque.x(), torque.y(), torque.z()));
}

MotorCommands VehicleController::motors(const VehicleState& truth, const Eigen::Vector4d& wrench) const {
  const Eigen::Vector4d f = allocation_inverse_ * wrench;
  MotorCommands out;
  const double tau = vehicle_.motor_time_constant_s;
  const double lead =
      gains_.motor_response_s > 0.0 && tau > gains_.motor_response_s ? tau / gains_.motor_response_s : 1.0;
  for (int i = 0; i < 4; ++i) {
    // tau f' = target - f; asking for f' = (demand - f) / response gives the target below.
    const double demand_N = std::clamp(f[i], 0.0, vehicle_.motor_thrust_max_N);
    const double target_N = truth.motor_thrust_N[i] + lead * (demand_N - truth.motor_thrust_N[i]);
    out.command[i] = std::clamp(target_N / vehicle_.motor_thrust_max_N, 0.0, 1.0);
  }
  return out;
}

}  // namespace hil
