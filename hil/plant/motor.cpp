#include "hil/plant/motor.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace hil {

double motor_target_thrust_N(double command, double gain, double thrust_max_N) {
  if (!std::isfinite(command)) return 0.0;
  return std::clamp(command, 0.0, 1.0) * gain * thrust_max_N;
}

double motor_thrust_after_N(double thrust_N, double target_N, double time_constant_s, double elapsed_s) {
  if (!(time_constant_s > 0.0)) return target_N;
  return target_N + (thrust_N - target_N) * std::exp(-elapsed_s / time_constant_s);
}

Vec3 motor_position_body_m(const VehicleConfig& vehicle, int motor) {
  const double a = vehicle.arm_length_m / std::numbers::sqrt2;
  switch (motor) {
    case 0: return {a, -a, 0.0};
    case 1: return {-a, a, 0.0};
    case 2: return {a, a, 0.0};
    default: return {-a, -a, 0.0};
  }
}

double motor_yaw_sign(int motor) { return motor < 2 ? -1.0 : 1.0; }

BodyWrench rotor_wrench(const VehicleConfig& vehicle, const std::array<double, 4>& thrust_N) {
  BodyWrench w;
  for (int i = 0; i < 4; ++i) {
    // r x (0, 0, T) = (r_y T, -r_x T, 0): the thrust along body z, written out (this runs three
    // times per integration step and vehicle).
    const Vec3 r = motor_position_body_m(vehicle, i);
    w.force_N.z() += thrust_N[i];
    w.torque_Nm.x() += r.y() * thrust_N[i];
    w.torque_Nm.y() -= r.x() * thrust_N[i];
    w.torque_Nm.z() += motor_yaw_sign(i) * vehicle.yaw_moment_per_thrust_m * thrust_N[i];
  }
  return w;
}

}  // namespace hil
