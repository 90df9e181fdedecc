#include "hil/plant/pole_drag.hpp"

#include <algorithm>
#include <cmath>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace hil {

Wrench pole_drag(const PoleConfig& pole, const Vec3& velocity_mps, const Vec3& rate_radps, const Vec3& axis) {
  Wrench w;
  const int segments = pole.drag_segments > 0 ? pole.drag_segments : 1;
  const double length_m = 2.0 * pole.half_length_m;
  const double dxi_m = length_m / segments;
  // xi runs from end 0 to end 1, measured from the centre of mass (it need not be the middle).
  const double end0_xi_m = pole.end_along_axis_m(0);
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
  int j = 0;
#if defined(__SSE2__)
  // Two segments at a time: the square roots, which bound the cost, in pairs (sqrtpd). The sums
  // then add the even and the odd segments apart, which moves them by rounding only (the test
  // against the point-by-point rule holds them to 1e-12 of the wrench's scale).
  {
    const __m128d end0_xi = _mm_set1_pd(end0_xi_m);
    const __m128d step = _mm_set1_pd(dxi_m);
    const __m128d zero = _mm_setzero_pd();
    const __m128d aa2 = _mm_set1_pd(aa), as22 = _mm_set1_pd(as2), ss2 = _mm_set1_pd(ss);
    const __m128d axial2 = _mm_set1_pd(axial_sq);
    __m128d index = _mm_set_pd(1.5, 0.5);  // (j + 0.5, j + 1.5), low lane first
    const __m128d two = _mm_set1_pd(2.0);
    __m128d r_sum = zero, xi_r_sum = zero, xi_speed_sum = zero, xi2_speed_sum = zero;
    for (; j + 1 < segments; j += 2) {
      const __m128d xi = _mm_add_pd(end0_xi, _mm_mul_pd(index, step));
      const __m128d across_sq =
          _mm_max_pd(_mm_add_pd(aa2, _mm_mul_pd(xi, _mm_add_pd(as22, _mm_mul_pd(xi, ss2)))), zero);
      const __m128d r = _mm_sqrt_pd(across_sq);
      const __m128d speed = _mm_sqrt_pd(_mm_add_pd(across_sq, axial2));
      r_sum = _mm_add_pd(r_sum, r);
      xi_r_sum = _mm_add_pd(xi_r_sum, _mm_mul_pd(xi, r));
      xi_speed_sum = _mm_add_pd(xi_speed_sum, _mm_mul_pd(xi, speed));
      xi2_speed_sum = _mm_add_pd(xi2_speed_sum, _mm_mul_pd(_mm_mul_pd(xi, xi), speed));
      index = _mm_add_pd(index, two);
    }
    auto total = [](__m128d x) { return _mm_cvtsd_f64(_mm_add_sd(x, _mm_unpackhi_pd(x, x))); };
    sum_r = total(r_sum);
    sum_xi_r = total(xi_r_sum);
    sum_xi_speed = total(xi_speed_sum);
    sum_xi2_speed = total(xi2_speed_sum);
  }
#endif
  for (; j < segments; ++j) {
    const double xi_m = end0_xi_m + (j + 0.5) * dxi_m;
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
