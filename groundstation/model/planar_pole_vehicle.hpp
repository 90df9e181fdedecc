// The planar (xz-plane) quadrocopter-pole model used to design the throw (paper, Section III-A,
// Fig. 4): the vehicle with pitch theta only (phi = psi = 0) and the pole pivoting at the
// vehicle's centre of gravity with tilt alpha from the vertical, positive towards +x
// (a = L sin alpha, eq. (32)).
//
// Templated on the scalar type so that Eigen's AutoDiffScalar (planning, LQR linearisation)
// runs through the same code as double.
//
// Derivation (the paper's appendix is not available; docs/paper-notes.md). The pivot p_q accelerates with
//   p_q'' = a_q (sin theta, cos theta) - (0, g)                                 eq. (4), planar
// and the pole's centre is p_p = p_q + L (sin alpha, cos alpha) (eq. (23), (24) with b = 0).
// In the pivot's frame the rod feels the effective gravity g - p_q'' = -a_q (sin theta, cos theta):
// only the thrust direction matters. The generalised force on alpha is
//   m_p (-a_q)(sin theta, cos theta) . L (cos alpha, -sin alpha) = m_p a_q L sin(alpha - theta)
// and the rod's inertia about the pivot is Theta + m_p L^2 = (4/3) m_p L^2 (eq. (9)), so the
// Lagrangian (28) reduces to the pendulum equation
//   (4/3) L alpha'' = a_q sin(alpha - theta).
// Hover (a_q = g, theta = 0) gives alpha'' = (3g / 4L) sin alpha: the upright pole is unstable,
// as it must be.
//
// Normal force. Newton for the rod's centre: m_p p_p'' = F + m_p (0, -g), with F the contact
// force the vehicle exerts on the rod. Its component along the plate normal (sin theta, cos theta):
//   F_N / m_p = a_q - L alpha'' sin(alpha - theta) - L alpha'^2 cos(alpha - theta)
//             = a_q - (3/4) a_q sin^2(alpha - theta) - L alpha'^2 cos(alpha - theta).
// This replaces the printed eq. (33), which is dimensionally inconsistent (its second term lacks
// a_q). The pole leaves the plate when F_N < 0 (Section III-A).
//
// At the printed Fig. 5 end state (alpha = 0.48, theta = -0.48, alpha' = 2.5, a_q = 4.48) this
// F_N / m_p is -0.159 m/s^2, and over every value that rounds to those digits it stays within
// [-0.26, -0.06]: the printed numbers are not a launch state of this model. The printed eq. (33),
// taken literally, gives +0.003 m/s^2 there, so the printed a_q,T appears to come from it. The
// planner therefore solves F_N = 0 for a_q,T (planar_launch_thrust_mps2: 4.799 m/s^2).
#pragma once

#include <Eigen/Core>
#include <cmath>

#include "pa/constants.hpp"

namespace gs::model {

struct PlanarPoleVehicleParams {
  double pole_half_length_m = pa::kPoleHalfLength_m;  // L
  double gravity_mps2 = pa::kGravity_mps2;            // g
};

// State s = (x, z, vx, vz, theta, alpha, alpha_dot): SI (m, m/s, rad, rad/s).
// Input u = (a_q, Omega_y): mass-normalised collective thrust (m/s^2) and pitch rate (rad/s).
namespace planar {
inline constexpr int kStateSize = 7;
inline constexpr int kInputSize = 2;
enum StateIndex : int { kX = 0, kZ = 1, kVx = 2, kVz = 3, kTheta = 4, kAlpha = 5, kAlphaDot = 6 };
enum InputIndex : int { kThrust = 0, kPitchRate = 1 };
}  // namespace planar

template <typename Scalar>
using PlanarState = Eigen::Matrix<Scalar, planar::kStateSize, 1>;
template <typename Scalar>
using PlanarInput = Eigen::Matrix<Scalar, planar::kInputSize, 1>;

// alpha'' from (4/3) L alpha'' = a_q sin(alpha - theta); see the derivation above.
template <typename Scalar>
Scalar planar_pole_angular_acceleration_radps2(const Scalar& theta_rad, const Scalar& alpha_rad,
                                               const Scalar& thrust_mps2,
                                               const PlanarPoleVehicleParams& params = {}) {
  using std::sin;
  return thrust_mps2 * sin(alpha_rad - theta_rad) * (0.75 / params.pole_half_length_m);
}

// F_N / m_p, the plate-normal contact force per unit pole mass (m/s^2); replaces eq. (33).
template <typename Scalar>
Scalar planar_normal_force_per_mass_mps2(const Scalar& theta_rad, const Scalar& alpha_rad,
                                         const Scalar& alpha_dot_radps, const Scalar& thrust_mps2,
                                         const PlanarPoleVehicleParams& params = {}) {
  using std::cos;
  using std::sin;
  const Scalar delta = alpha_rad - theta_rad;
  const Scalar sin_delta = sin(delta);
  return thrust_mps2 - 0.75 * thrust_mps2 * sin_delta * sin_delta -
         params.pole_half_length_m * alpha_dot_radps * alpha_dot_radps * cos(delta);
}

template <typename Scalar>
Scalar planar_normal_force_per_mass_mps2(const PlanarState<Scalar>& s, const PlanarInput<Scalar>& u,
                                         const PlanarPoleVehicleParams& params = {}) {
  return planar_normal_force_per_mass_mps2<Scalar>(s(planar::kTheta), s(planar::kAlpha), s(planar::kAlphaDot),
                                                   u(planar::kThrust), params);
}

// s' = f(s, u): eq. (4) and (5) in the xz-plane (phi = psi = 0, so theta' = Omega_y) and the
// pendulum equation above.
template <typename Scalar>
PlanarState<Scalar> planar_pole_vehicle_dynamics(const PlanarState<Scalar>& s, const PlanarInput<Scalar>& u,
                                                 const PlanarPoleVehicleParams& params = {}) {
  using std::cos;
  using std::sin;
  const Scalar& theta = s(planar::kTheta);
  const Scalar& a_q = u(planar::kThrust);
  PlanarState<Scalar> s_dot;
  s_dot(planar::kX) = s(planar::kVx);
  s_dot(planar::kZ) = s(planar::kVz);
  s_dot(planar::kVx) = a_q * sin(theta);
  s_dot(planar::kVz) = a_q * cos(theta) - params.gravity_mps2;
  s_dot(planar::kTheta) = u(planar::kPitchRate);
  s_dot(planar::kAlpha) = s(planar::kAlphaDot);
  s_dot(planar::kAlphaDot) =
      planar_pole_angular_acceleration_radps2<Scalar>(theta, s(planar::kAlpha), a_q, params);
  return s_dot;
}

// A = df/ds, B = df/du at (s, u), by forward automatic differentiation of
// planar_pole_vehicle_dynamics (planar_pole_vehicle.cpp): the linearisation for the LQR designs.
struct PlanarLinearisation {
  Eigen::Matrix<double, planar::kStateSize, planar::kStateSize> A;
  Eigen::Matrix<double, planar::kStateSize, planar::kInputSize> B;
};
PlanarLinearisation linearise_planar_pole_vehicle(const PlanarState<double>& s, const PlanarInput<double>& u,
                                                  const PlanarPoleVehicleParams& params = {});

// The launch condition F_N = 0 (Section III-A) solved for the thrust: with delta = alpha - theta,
// a_q (1 - (3/4) sin^2 delta) = L alpha'^2 cos delta. The bracket is at least 1/4, so the
// solution always exists (it is negative when cos delta < 0: no positive thrust launches then).
inline double planar_launch_thrust_mps2(double theta_rad, double alpha_rad, double alpha_dot_radps,
                                        const PlanarPoleVehicleParams& params = {}) {
  const double delta = alpha_rad - theta_rad;
  const double sin_delta = std::sin(delta);
  return params.pole_half_length_m * alpha_dot_radps * alpha_dot_radps * std::cos(delta) /
         (1.0 - 0.75 * sin_delta * sin_delta);
}

// The launch condition solved for the pole rate alpha' >= 0 at a given thrust. Returns NaN when
// no real rate exists (cos delta <= 0).
inline double planar_launch_pole_rate_radps(double theta_rad, double alpha_rad, double thrust_mps2,
                                            const PlanarPoleVehicleParams& params = {}) {
  const double delta = alpha_rad - theta_rad;
  const double sin_delta = std::sin(delta);
  const double cos_delta = std::cos(delta);
  const double rate_sq =
      thrust_mps2 * (1.0 - 0.75 * sin_delta * sin_delta) / (params.pole_half_length_m * cos_delta);
  if (!(cos_delta > 0.0) || !(rate_sq >= 0.0)) return std::nan("");
  return std::sqrt(rate_sq);
}

}  // namespace gs::model
