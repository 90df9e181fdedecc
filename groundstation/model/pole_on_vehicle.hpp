// The pole balanced on a quadrocopter, Section II-B-2, eq. (23)-(31), in 3D.
//
// The pole pivots at the vehicle's centre of mass p_q (eq. 23: p_p = p_q + L n, n pointing from
// the pivot to the pole's centre) and its attitude is the deflection (a, b) of its centre from
// the pivot, L n = (a, b, sqrt(L^2 - a^2 - b^2)) (eq. 24), valid while a^2 + b^2 < L^2 (the pole
// above the pivot's horizontal plane). The vehicle is not affected by the pole (Section II).
//
// Derivation of (28), (29) (the paper's appendix is not available; docs/paper-notes.md). Write r = L n =
// (a, b, c), c = sqrt(L^2 - a^2 - b^2), so r' = (a', b', c') with c' = -(a a' + b b') / c (26).
// Because n . n' = 0, |Omega~|^2 = |n x n'|^2 = |n'|^2 = |r'|^2 / L^2 (27), and Theta / L^2 =
// m_p / 3 (9), so the Lagrangian (25) is
//   Lag = 1/2 m_p |p_q' + r'|^2 + 1/2 (m_p / 3) |r'|^2 - m_p g (z_q + c).
// With e_i = dr/dq_i for q = (a, b) (e_a = (1, 0, -a/c), e_b = (0, 1, -b/c)) and the identity
// d(r')/dq_i = d(e_i)/dt,
//   d/dt dLag/dq_i' = m_p (p_q'' + (4/3) r'') . e_i + m_p (p_q' + (4/3) r') . e_i'
//   dLag/dq_i       = m_p (p_q' + (4/3) r') . e_i' - m_p g e_z . e_i,
// and (28), (29) become
//   ((4/3) r'' + f) . e_i = 0,   f = p_q'' + (0, 0, g)   (i = a, b),
// f being the pivot's specific force (for a vehicle, a_q times its thrust axis, eq. 4): only the
// thrust acts on the pole, gravity and the vehicle's acceleration combine into it. e_a, e_b span
// the sphere's tangent plane, so (4/3) r'' + f is parallel to r; with r . r'' = -|r'|^2 (from
// |r| = L) this gives
//   r'' = -(3/4) f + mu r,   mu = ((3/4) f . r - |r'|^2) / L^2,
// whose x and y components are a'' and b''. In the plane (b = 0, a = L sin alpha, f = a_q
// (sin theta, 0, cos theta)) the tangential component is (4/3) L alpha'' = a_q sin(alpha - theta),
// the pendulum equation of docs/paper-notes.md.
#pragma once

#include <Eigen/Dense>

#include "groundstation/model/pole_free_flight.hpp"
#include "groundstation/model/vehicle.hpp"

namespace gs::model {

// The pole part of s_qp (31): deflections a, b (m) and their rates (m/s). Also carries the time
// derivative (a', b', a'', b'') when returned by pole_on_vehicle_derivative().
struct PoleOnVehicleState {
  double a_m = 0.0;
  double b_m = 0.0;
  double a_dot_mps = 0.0;
  double b_dot_mps = 0.0;
};

PoleOnVehicleState operator+(const PoleOnVehicleState& lhs, const PoleOnVehicleState& rhs);
PoleOnVehicleState operator*(double scale, const PoleOnVehicleState& state);

// s_qp = (s_q, a, b, a', b'), eq. (31); also carries its time derivative.
struct VehiclePoleState {
  VehicleState vehicle;
  PoleOnVehicleState pole;
};

VehiclePoleState operator+(const VehiclePoleState& lhs, const VehiclePoleState& rhs);
VehiclePoleState operator*(double scale, const VehiclePoleState& state);

// n from (a, b), eq. (24). Requires a^2 + b^2 < L^2.
Eigen::Vector3d pole_direction_on_vehicle(const PoleOnVehicleState& pole, const PoleParams& params);
// r' = L n' = (a', b', c'), eq. (26) without the pivot velocity.
Eigen::Vector3d pole_centre_velocity_relative_to_pivot_mps(const PoleOnVehicleState& pole,
                                                           const PoleParams& params);

// (a'', b'') from eq. (28), (29), given the pivot's acceleration p_q'' (inertial, m/s^2).
Eigen::Vector2d pole_on_vehicle_acceleration_mps2(const PoleOnVehicleState& pole,
                                                  const Eigen::Vector3d& pivot_acceleration_mps2,
                                                  const PoleParams& params);

// (a', b', a'', b'') for a pivot with the given acceleration.
PoleOnVehicleState pole_on_vehicle_derivative(const PoleOnVehicleState& pole,
                                              const Eigen::Vector3d& pivot_acceleration_mps2,
                                              const PoleParams& params);

// s_qp' = f_qp(s_qp, u_q), eq. (30): f_q (8) and the pole equations driven by (4).
VehiclePoleState vehicle_pole_dynamics(const VehiclePoleState& state, const VehicleInput& input,
                                       const PoleParams& params);

// The Lagrangian (25)-(27) for a pivot at pivot_p_m moving with pivot_v_mps (J).
double pole_on_vehicle_lagrangian_J(const PoleOnVehicleState& pole, const Eigen::Vector3d& pivot_p_m,
                                    const Eigen::Vector3d& pivot_v_mps, const PoleParams& params);
// The pole's total energy T + V for the same pivot (J); potential zero at z = 0.
double pole_on_vehicle_energy_J(const PoleOnVehicleState& pole, const Eigen::Vector3d& pivot_p_m,
                                const Eigen::Vector3d& pivot_v_mps, const PoleParams& params);

// The free-flight state (21) of a pole on a pivot: p_p = p_q + L n (23), p_p' from (26),
// Omega_p = n x n' (27) (normal to n, as PoleState requires).
PoleState free_flight_state_from_pole_on_vehicle(const PoleOnVehicleState& pole,
                                                 const Eigen::Vector3d& pivot_p_m,
                                                 const Eigen::Vector3d& pivot_v_mps,
                                                 const PoleParams& params);

// The inverse for a pole whose n points from the pivot up to its centre (n_z > 0): a, b from
// L n, a', b' from L n' = L Omega_p x n. The pivot's velocity is not needed.
PoleOnVehicleState pole_on_vehicle_state_from_free_flight(const PoleState& pole, const PoleParams& params);

}  // namespace gs::model
