#include "hil/plant/pole_drag.hpp"

#include <algorithm>
#include <cmath>

namespace hil {

Wrench pole_drag(const PoleConfig& pole, const Vec3& velocity_mps, const Vec3& rate_radps, const Vec3& axis) {
  Wrench w;
  const int segments = pole.drag_segments > 0 ? pole.drag_segments : 1;
  const double length_m = 2.0 * pole.half_length_m;
  const double dxi_m = length_m / segments;
  // v(xi) = v_p + xi (omega x n) (12), and omega x n is across the pole: the axial part (13) is
  // the same at every point, and only the part across, a + xi s, varies along it. The midpoint
  // rule then needs two square roots per segment on scalars instead of vector norms.
  const double v_n = velocity_mps.dot(axis);
  const Vec3 v_axial = v_n * axis;        // (13)
  const Vec3 a = velocity_mps - v_axial;  // (14) at the centre
  const Vec3 s = rate_radps.cross(axis);  // d v / d xi
  const double aa = a.squaredNorm();
  const double as2 = 2.0 * a.dot(s);
  const double ss = s.squaredNorm();
  const double axial_sq = v_n * v_n;
  double sum_r = 0.0, sum_xi_r = 0.0, sum_xi_speed = 0.0, sum_xi2_speed = 0.0;
  for (int j = 0; j < segments; ++j) {
    const double xi_m = -pole.half_length_m + (j + 0.5) * dxi_m;
    const double across_sq = std::max(0.0, aa + xi_m * (as2 + xi_m * ss));  // |v_across(xi)|^2
    const double r = std::sqrt(across_sq);
    const double speed = std::sqrt(across_sq + axial_sq);  // |v(xi)|
    sum_r += r;
    sum_xi_r += xi_m * r;
    sum_xi_speed += xi_m * speed;
    sum_xi2_speed += xi_m * xi_m * speed;
  }
  // (10), (11): the axial force is exact with one point.
  w.force_N = -(pole.drag_axial_kgpm2 * std::abs(v_n) * length_m) * v_axial -
              (pole.drag_normal_kgpm2 * dxi_m) * (sum_r * a + sum_xi_r * s);
  // (15): (xi n) x (|v| v) = xi |v| n x (a + xi s), as n x v_axial = 0.
  w.torque_Nm = -(pole.drag_rotational_kgpm2 * dxi_m) * axis.cross(sum_xi_speed * a + sum_xi2_speed * s);
  return w;
}

}  // namespace hil
