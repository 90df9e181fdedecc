#include "groundstation/model/pole_free_flight.hpp"

#include <algorithm>
#include <cmath>

#include "groundstation/model/rk4.hpp"

namespace gs::model {
namespace {

// 4-point Gauss-Legendre rule on [-1, 1] (exact for polynomials of degree <= 7).
constexpr int kGaussPoints = 4;
constexpr double kGaussNodes[kGaussPoints] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
                                              0.8611363115940526};
constexpr double kGaussWeights[kGaussPoints] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
                                                0.3478548451374538};

// K_k = integral over t in [t0, t1] of t^k sqrt(t^2 + a^2), k = 0, 1, 2, in closed form:
//   K0 = 1/2 [t s + a^2 asinh(t/a)],  K1 = 1/3 [s^3],
//   K2 = 1/8 [t s (2 t^2 + a^2) - a^4 asinh(t/a)],   s = sqrt(t^2 + a^2).
// asinh(t1/a) - asinh(t0/a) = log((t1 + s1) / (t0 + s0)), with t + s = a^2 / (s - t) for t < 0
// (no cancellation); for a -> 0 the a^2 log terms vanish. s1^3 - s0^3 is factored to avoid
// cancellation. Used only for a < 3L and |xi*| < 4L, i.e. |t| < 5L (see pole_drag), where the
// rounding error stays within a few hundred ulp of the integrals.
struct SqrtMoments {
  double k0;
  double k1;
  double k2;
};

inline SqrtMoments sqrt_moments(double t0, double t1, double a_sq) {
  const double s0 = std::sqrt(t0 * t0 + a_sq);
  const double s1 = std::sqrt(t1 * t1 + a_sq);
  double log_ratio = 0.0;
  if (a_sq > 1e-30) {
    const double e1 = t1 >= 0.0 ? t1 + s1 : a_sq / (s1 - t1);
    const double e0 = t0 >= 0.0 ? t0 + s0 : a_sq / (s0 - t0);
    log_ratio = std::log(e1 / e0);
  }
  const double s_diff = (t1 * t1 - t0 * t0) / (s1 + s0);
  return {0.5 * (t1 * s1 - t0 * s0 + a_sq * log_ratio), s_diff * (s1 * s1 + s1 * s0 + s0 * s0) / 3.0,
          (t1 * s1 * (2.0 * t1 * t1 + a_sq) - t0 * s0 * (2.0 * t0 * t0 + a_sq)) / 8.0 -
              a_sq * a_sq * log_ratio / 8.0};
}

}  // namespace

PoleParams without_drag(PoleParams params) {
  params.drag_axial = 0.0;
  params.drag_normal = 0.0;
  params.drag_rotational = 0.0;
  return params;
}

double pole_inertia_kgm2(const PoleParams& params) {
  return params.mass_kg * params.half_length_m * params.half_length_m / 3.0;
}

// The velocity of the pole point at xi is v(xi) = v + xi w with w = Omega x n (12). Split
// v = v_ax n + u with u normal to n; w is normal to n as well.
//  - Axial part (13): v_z(xi) = v_ax n does not depend on xi, so (10) is exact in closed form:
//    F_z = -c_z 2L |v_ax| v_ax n.
//  - Normal part (14): v_xy(xi) = u + xi w is affine in xi. With xi* = -(u . w) / |w|^2,
//    t = xi - xi* and e = u + xi* w (normal to w), v_xy = t w + e and
//      |v_xy| = |w| sqrt(t^2 + d^2),  d^2 = |e|^2 / |w|^2,
//      |v|    = |w| sqrt(t^2 + D^2),  D^2 = d^2 + v_ax^2 / |w|^2   (n x v = n x v_xy in (15)).
//    So (11) and (15) are moments of sqrt(t^2 + a^2) times polynomials in t:
//      int |v_xy| v_xy dxi    = |w| (w K1(d) + e K0(d))
//      int xi |v| v_xy dxi    = |w| (w (K2(D) + xi* K1(D)) + e (K1(D) + xi* K0(D)))
//    over t in [-L - xi*, L - xi*]. The |.| makes the integrands non-smooth where the speed
//    vanishes (planar flight: d = 0, a kink inside the pole) or nearly so (the complex
//    singularity xi* +/- i a): a plain Gauss rule converges slowly there (a 2 x 6-point rule
//    split at xi* still errs by 1.5e-4). These moments are evaluated in closed form
//    (sqrt_moments, exact up to rounding) whenever the singularity lies within 3L of the pole;
//    further away the integrand is smooth on [-L, L] and a single 4-point Gauss rule errs by
//    below 1e-6 (Bernstein ellipse rho >= 5.8), with no log and no cancellation from a large
//    |xi*| or a. Pinned against a fine trapezoid of (10)-(15) in the tests.
PoleDrag pole_drag(const PoleState& state, const PoleParams& params) {
  const double length = params.half_length_m;
  const Eigen::Vector3d& n = state.n;
  const double v_axial = state.v_mps.dot(n);
  const Eigen::Vector3d u = state.v_mps - v_axial * n;
  const Eigen::Vector3d w = state.omega_radps.cross(n);

  PoleDrag drag;
  drag.axial_force_N = (-params.drag_axial * 2.0 * length * std::abs(v_axial) * v_axial) * n;

  const double w_sq = w.squaredNorm();
  const double v_axial_sq = v_axial * v_axial;
  const double far_sq = 9.0 * length * length;
  // Squared distance of the complex singularity xi* +/- i a from [-L, L]; infinite for w = 0.
  double xi_star = 0.0;
  double d_sq = 0.0;
  double outside_sq = far_sq;
  Eigen::Vector3d e = u;
  double big_d_sq = far_sq;
  if (w_sq > 1e-12 * (u.squaredNorm() + v_axial_sq) && w_sq > 1e-300) {
    const double inv_w_sq = 1.0 / w_sq;
    xi_star = -u.dot(w) * inv_w_sq;
    e = u + xi_star * w;
    d_sq = e.squaredNorm() * inv_w_sq;
    big_d_sq = d_sq + v_axial_sq * inv_w_sq;
    const double outside = std::max(std::abs(xi_star) - length, 0.0);
    outside_sq = outside * outside;
  }
  const bool normal_far = outside_sq + d_sq >= far_sq;
  const bool torque_far = outside_sq + big_d_sq >= far_sq;

  Eigen::Vector3d normal_integral = Eigen::Vector3d::Zero();
  Eigen::Vector3d torque_integral = Eigen::Vector3d::Zero();
  if (normal_far || torque_far) {
    for (int k = 0; k < kGaussPoints; ++k) {
      const double xi = length * kGaussNodes[k];
      const Eigen::Vector3d v_xy = u + xi * w;
      const double speed_xy_sq = v_xy.squaredNorm();
      const double weight = length * kGaussWeights[k];
      if (normal_far) normal_integral += (weight * std::sqrt(speed_xy_sq)) * v_xy;
      if (torque_far) {
        torque_integral += (weight * xi * std::sqrt(speed_xy_sq + v_axial_sq)) * v_xy;
      }
    }
  }
  const double t0 = -length - xi_star;
  const double t1 = length - xi_star;
  const double w_norm = std::sqrt(w_sq);
  if (!normal_far) {
    const SqrtMoments m = sqrt_moments(t0, t1, d_sq);
    normal_integral = w_norm * (m.k1 * w + m.k0 * e);
  }
  if (!torque_far) {
    const SqrtMoments m = sqrt_moments(t0, t1, big_d_sq);
    torque_integral = w_norm * ((m.k2 + xi_star * m.k1) * w + (m.k1 + xi_star * m.k0) * e);
  }
  drag.normal_force_N = -params.drag_normal * normal_integral;          // (11)
  drag.torque_Nm = -params.drag_rotational * n.cross(torque_integral);  // (15)
  return drag;
}

PoleState pole_free_flight_derivative(const PoleState& state, const PoleParams& params) {
  const PoleDrag drag = pole_drag(state, params);
  PoleState rate;
  rate.p_m = state.v_mps;
  rate.v_mps = (drag.axial_force_N + drag.normal_force_N) / params.mass_kg -
               Eigen::Vector3d(0.0, 0.0, params.gravity_mps2);    // (16)
  rate.n = state.omega_radps.cross(state.n);                      // (22)
  rate.omega_radps = drag.torque_Nm / pole_inertia_kgm2(params);  // (19)
  return rate;
}

PoleState normalised_pole_state(const PoleState& state) {
  PoleState out = state;
  out.n = state.n.normalized();
  out.omega_radps -= out.omega_radps.dot(out.n) * out.n;
  return out;
}

// The input is normalised too: a spin left in Omega would, under (19), leak into the normal rate
// within the step (header comment) and make the result depend on the step length.
PoleState pole_free_flight_step(const PoleState& state, double dt_s, const PoleParams& params) {
  return normalised_pole_state(
      rk4_step([&params](const PoleState& s) { return pole_free_flight_derivative(s, params); },
               normalised_pole_state(state), dt_s));
}

PoleState propagate_pole(const PoleState& state, double duration_s, double max_step_s,
                         const PoleParams& params) {
  PoleState s = state;
  if (!(duration_s > 0.0) || !(max_step_s > 0.0)) return s;
  const int steps = std::max(1, static_cast<int>(std::ceil(duration_s / max_step_s - 1e-12)));
  const double dt = duration_s / steps;
  for (int i = 0; i < steps; ++i) s = pole_free_flight_step(s, dt, params);
  return s;
}

double pole_energy_J(const PoleState& state, const PoleParams& params) {
  const Eigen::Vector3d omega_normal = state.omega_radps - state.omega_radps.dot(state.n) * state.n;
  return 0.5 * params.mass_kg * state.v_mps.squaredNorm() +
         0.5 * pole_inertia_kgm2(params) * omega_normal.squaredNorm() +
         params.mass_kg * params.gravity_mps2 * state.p_m.z();
}

Eigen::Vector3d pole_tail_end_m(const PoleState& state, const PoleParams& params) {
  return state.p_m - params.half_length_m * state.n;
}

Eigen::Vector3d pole_head_end_m(const PoleState& state, const PoleParams& params) {
  return state.p_m + params.half_length_m * state.n;
}

Eigen::Vector3d pole_lower_end_m(const PoleState& state, const PoleParams& params) {
  return state.n.z() >= 0.0 ? pole_tail_end_m(state, params) : pole_head_end_m(state, params);
}

}  // namespace gs::model
