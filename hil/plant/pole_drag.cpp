#include "hil/plant/pole_drag.hpp"

namespace hil {

Wrench pole_drag(const PoleConfig& pole, const Vec3& velocity_mps, const Vec3& rate_radps, const Vec3& axis) {
  Wrench w;
  const int segments = pole.drag_segments > 0 ? pole.drag_segments : 1;
  const double length_m = 2.0 * pole.half_length_m;
  const double dxi_m = length_m / segments;
  const Vec3 spin_velocity_per_m = rate_radps.cross(axis);  // d v / d xi
  for (int j = 0; j < segments; ++j) {
    const double xi_m = -pole.half_length_m + (j + 0.5) * dxi_m;
    const Vec3 v = velocity_mps + xi_m * spin_velocity_per_m;  // (12)
    const Vec3 v_axial = v.dot(axis) * axis;                   // (13)
    const Vec3 v_across = v - v_axial;                         // (14)
    w.force_N -= (pole.drag_axial_kgpm2 * v_axial.norm() * v_axial +
                  pole.drag_normal_kgpm2 * v_across.norm() * v_across) *
                 dxi_m;                                                                     // (10), (11)
    w.torque_Nm -= pole.drag_rotational_kgpm2 * (xi_m * axis).cross(v.norm() * v) * dxi_m;  // (15)
  }
  return w;
}

}  // namespace hil
