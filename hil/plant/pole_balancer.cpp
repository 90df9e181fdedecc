#include "hil/plant/pole_balancer.hpp"

#include <cmath>

namespace hil {

BalancerGains balancer_gains(double half_length_m, double gravity_mps2, double lambda_radps) {
  const double a = 3.0 * gravity_mps2 / (4.0 * half_length_m);
  const double b = 3.0 / (4.0 * half_length_m);
  const double l = lambda_radps;
  // Match s^4 + 4 l s^3 + 6 l^2 s^2 + 4 l^3 s + l^4.
  BalancerGains g;
  g.k_position = -l * l * l * l / a;
  g.k_velocity = -4.0 * l * l * l / a;
  g.k_tilt = (g.k_position - a - 6.0 * l * l) / b;
  g.k_tilt_rate = (g.k_velocity - 4.0 * l) / b;
  return g;
}

Vec3 balance_acceleration(const BalancerGains& gains, const PoleState& pole, int supported_end,
                          const VehicleState& vehicle, const Vec3& reference_m) {
  // Unit vector from the supported end to the centre, and its rate.
  const Vec3 up = supported_end == 0 ? pole.axis() : Vec3(-pole.axis());
  const Vec3 up_rate = pole.body.rate_inertial_radps().cross(up);
  Vec3 u = Vec3::Zero();
  for (int axis = 0; axis < 2; ++axis) {
    // Tilt towards +x (or +y) in the vertical plane of that axis.
    const double h = up[axis];
    const double v = up.z();
    const double tilt = std::atan2(h, v);
    const double tilt_rate = (up_rate[axis] * v - h * up_rate.z()) / (h * h + v * v);
    const double x = vehicle.body.position_m[axis] - reference_m[axis];
    const double xdot = vehicle.body.velocity_mps[axis];
    u[axis] = -(gains.k_position * x + gains.k_velocity * xdot + gains.k_tilt * tilt +
                gains.k_tilt_rate * tilt_rate);
  }
  return u;
}

}  // namespace hil
