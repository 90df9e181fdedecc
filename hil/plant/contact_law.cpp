#include "hil/plant/contact_law.hpp"

#include <algorithm>
#include <cmath>

namespace hil {

double contact_normal_force_N(const ContactLaw& law, double depth_m, double normal_velocity_mps) {
  if (!(depth_m > 0.0)) return 0.0;
  const double rate_mps = -normal_velocity_mps;
  const double damper_N =
      rate_mps > 0.0
          ? law.damping_force_max_N * std::tanh(law.damping_Nspm * rate_mps / law.damping_force_max_N)
          : law.rebound_damping_Nspm * rate_mps;
  // A contact that pulled would glue a separating point to the surface: only push.
  return std::max(0.0, law.stiffness_Npm * depth_m + damper_N);
}

Vec3 contact_force_N(const ContactLaw& law, const Vec3& normal, double depth_m,
                     const Vec3& relative_velocity_mps, const Vec3& anchor_offset_m) {
  const double v_n = relative_velocity_mps.dot(normal);
  const double f_n = contact_normal_force_N(law, depth_m, v_n);
  if (f_n <= 0.0) return Vec3::Zero();
  const Vec3 v_t = relative_velocity_mps - v_n * normal;
  const Vec3 d_t = anchor_offset_m - anchor_offset_m.dot(normal) * normal;
  Vec3 f_t = -law.tangential_stiffness_Npm * d_t - law.tangential_damping_Nspm * v_t;
  const double limit = law.friction * f_n;
  const double magnitude = f_t.norm();
  if (magnitude > limit) f_t *= limit / magnitude;  // sliding: Coulomb friction against the motion
  return f_n * normal + f_t;
}

Vec3 slipped_anchor_offset_m(const ContactLaw& law, double normal_force_N, const Vec3& anchor_offset_m) {
  const double limit_m = law.friction * std::max(0.0, normal_force_N) / law.tangential_stiffness_Npm;
  const double length_m = anchor_offset_m.norm();
  if (length_m <= limit_m) return anchor_offset_m;
  return anchor_offset_m * (limit_m / length_m);
}

}  // namespace hil
