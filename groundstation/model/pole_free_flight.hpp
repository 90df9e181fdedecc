// The pole in free flight, Section II-B-1, eq. (9)-(22), in 3D: a thin rod of length 2L and mass
// m_p under gravity and quadratic aerodynamic drag, state s_p = (p_p, p_p', n, Omega_p) (21).
//
// Conventions: inertial frame z up, gravity (0, 0, -g). n is the unit vector along the pole's
// z-axis; which end it points to is whatever the state says (the impact map picks the lower end).
//
// Spin about the pole axis. The rod has no inertia about its axis (eq. 9), so the spin
// Omega_p . n carries no energy and does not move n (n' = Omega_p x n only sees the normal
// part). The paper keeps the spin constant; with a non-zero spin eq. (19) would also turn the
// normal rate (the true law is Theta d(Omega_perp)/dt = M_drag, since the angular momentum is
// Theta Omega_perp by (18)). This model therefore keeps Omega_p normal to n: then (19) is exact,
// the spin stays zero analytically, and normalised_pole_state() removes the round-off.
#pragma once

#include <Eigen/Dense>

#include "pa/constants.hpp"

namespace gs::model {

struct PoleParams {
  double half_length_m = pa::kPoleHalfLength_m;      // L
  double mass_kg = pa::kPoleMass_kg;                 // m_p
  double drag_axial = pa::kPoleDragAxial;            // c_z, kg/m^2, eq. (10)
  double drag_normal = pa::kPoleDragNormal;          // c_xy, kg/m^2, eq. (11)
  double drag_rotational = pa::kPoleDragRotational;  // c_rot, kg/m^2, eq. (15)
  double gravity_mps2 = pa::kGravity_mps2;           // g
};

// The same parameters with c_z = c_xy = c_rot = 0 (drag off).
PoleParams without_drag(PoleParams params);

// Theta = m_p L^2 / 3, the rod's inertia about a transverse axis through its centre, eq. (9).
double pole_inertia_kgm2(const PoleParams& params);

// s_p = (p_p, p_p', n, Omega_p), eq. (21). The same struct carries the time derivative
// f_p(s_p) of eq. (20), each field then holding the rate of that field.
struct PoleState {
  Eigen::Vector3d p_m = Eigen::Vector3d::Zero();          // centre of mass
  Eigen::Vector3d v_mps = Eigen::Vector3d::Zero();        // centre velocity
  Eigen::Vector3d n = Eigen::Vector3d::UnitZ();           // unit, along the pole
  Eigen::Vector3d omega_radps = Eigen::Vector3d::Zero();  // inertial angular rate, normal to n
};

// Inline: the RK4 steps of the catch-point predictor run at every motion-capture frame.
inline PoleState operator+(const PoleState& lhs, const PoleState& rhs) {
  return {lhs.p_m + rhs.p_m, lhs.v_mps + rhs.v_mps, lhs.n + rhs.n, lhs.omega_radps + rhs.omega_radps};
}
inline PoleState operator*(double scale, const PoleState& state) {
  return {scale * state.p_m, scale * state.v_mps, scale * state.n, scale * state.omega_radps};
}

// The aerodynamic loads of eq. (10)-(15).
struct PoleDrag {
  Eigen::Vector3d axial_force_N = Eigen::Vector3d::Zero();   // F_drag,z (10)
  Eigen::Vector3d normal_force_N = Eigen::Vector3d::Zero();  // F_drag,xy (11)
  Eigen::Vector3d torque_Nm = Eigen::Vector3d::Zero();       // M_drag about the centre (15)
};

// Eq. (10)-(15), integrated along the pole. See pole_free_flight.cpp for the quadrature.
PoleDrag pole_drag(const PoleState& state, const PoleParams& params);

// s_p' = f_p(s_p), eq. (20): (16), (19) and (22).
PoleState pole_free_flight_derivative(const PoleState& state, const PoleParams& params);

// n scaled to unit length and the spin Omega_p . n removed (see the header comment).
PoleState normalised_pole_state(const PoleState& state);

// One RK4 step of eq. (20) of length dt_s from normalised_pole_state(state), normalised again.
PoleState pole_free_flight_step(const PoleState& state, double dt_s, const PoleParams& params);

// Integrates eq. (20) over duration_s with steps of at most max_step_s (the last one shorter).
PoleState propagate_pole(const PoleState& state, double duration_s, double max_step_s,
                         const PoleParams& params);

// Total mechanical energy: translational + rotational + potential (zero at z = 0), in J.
double pole_energy_J(const PoleState& state, const PoleParams& params);

// The pole's end points p_p -/+ L n.
Eigen::Vector3d pole_tail_end_m(const PoleState& state, const PoleParams& params);  // p - L n
Eigen::Vector3d pole_head_end_m(const PoleState& state, const PoleParams& params);  // p + L n
// The lower of the two ends (the tail when n_z >= 0).
Eigen::Vector3d pole_lower_end_m(const PoleState& state, const PoleParams& params);

}  // namespace gs::model
