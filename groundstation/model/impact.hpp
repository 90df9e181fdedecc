// The catch: the impact map (35)-(40), the post-impact energy (41) and the optimal catching
// condition (42) of Section III-B, in 3D and in the xz-plane.
//
// The impact is totally inelastic with large friction: the pole's lower end sticks to the
// catching plate and becomes the pivot of the pole-on-vehicle model (23). The vehicle is not
// affected (its inertia is much larger). The impulse acts at the contact point, so the pole's
// angular momentum about that point is conserved through the impact.
//
// 3D impact map. Let n point from the contact end (the lower end, c = p - L n) to the centre and
// let Omega be normal to n (PoleState). The angular momentum about c is
//   H_c = Theta Omega + m_p L n x v                    (Theta Omega is the momentum about the
//                                                       centre by (18); n is frozen during impact)
// After the impact the contact point moves with the plate (velocity v_q): v+ = v_q + L Omega+ x n
// (the 3D form of (38), (39)), so n x v+ = n x v_q + L Omega+ and
//   H_c+ = (4/3) m_p L^2 Omega+ + m_p L n x v_q.
// Equating H_c- and H_c+:
//   Omega+ = 1/4 Omega- + 3/(4L) n x (v- - v_q).
// The impulse is Lambda = m_p (v+ - v-) ((35), (36)).
//
// Planar convention (this file's, used by the catch planner). In the xz-plane let alpha be the
// tilt of the contact-end-to-centre direction from the vertical, positive towards +x, so that
// x_p = x_c + L sin alpha, z_p = z_c + L cos alpha (as in the paper's impact equations), and
// |alpha| < pi/2 because the contact end is the lower one. alpha' = Omega_y (a rotation about +y
// turns +z towards +x). Then (n x v)_y = x' cos alpha - z' sin alpha and, for a plate at rest,
// the y-component of the map above is eq. (40):
//   alpha'+ = 1/4 alpha'- + 3/(4L) (x'- cos alpha - z'- sin alpha).
// Post-impact energy relative to the contact point (41):
//   E+ = m_p g L cos alpha + 1/2 m_p (L alpha'+)^2 + 1/2 Theta alpha'+^2
//      = m_p g L cos alpha + (2/3) m_p L^2 alpha'+^2.
// The pole swings up to the upright by itself iff E+ = E* = m_p g L and it turns towards the
// upright, i.e. it lies on the stable branch of the separatrix of (4/3) L alpha'' = g sin alpha:
//   (2/3) L^2 alpha'^2 = g L (1 - cos alpha) = 2 g L sin^2(alpha/2)
//   => alpha'+ = -sqrt(3 g / L) sin(alpha / 2)            (the sign turns it towards alpha = 0).
// Inserting (40) and multiplying by 4 gives this file's eq. (42):
//   C = alpha'- + (3/L) (x'- cos alpha - z'- sin alpha) + 4 sqrt(3 g / L) sin(alpha / 2) = 0,
// with C = 4 (alpha'+ - alpha'+_required) smooth in alpha. Multiplied by sgn(alpha) it reads
//   sgn(alpha) alpha'- + sgn(alpha) (3/L) (x' cos alpha - z' sin alpha)
//     + sqrt(24 g (1 - cos alpha) / L) = 0,
// which agrees with the printed (42) for alpha < 0 (the nominal catch, where the pole leans
// towards -x and turns towards +x) and differs in the sign of the middle term for alpha > 0:
// the printed form fixes one direction of rotation (docs/paper-notes.md).
#pragma once

#include <Eigen/Dense>

#include "groundstation/model/pole_free_flight.hpp"
#include "groundstation/model/pole_on_vehicle.hpp"

namespace gs::model {

// The same pole with n pointing from its lower end up to its centre (n_z >= 0); Omega unchanged
// (the same rigid-body motion).
PoleState with_lower_end_as_base(const PoleState& state);

// Angular momentum of the pole about a fixed point (kg m^2/s): Theta Omega_perp + m_p r x v.
Eigen::Vector3d pole_angular_momentum_about(const PoleState& state, const Eigen::Vector3d& point_m,
                                            const PoleParams& params);

struct ImpactResult {
  Eigen::Vector3d contact_point_m = Eigen::Vector3d::Zero();  // the lower end at impact
  PoleState after;                                            // n from the contact end up to the centre
  PoleOnVehicleState on_vehicle;                         // the same, in the pole-on-vehicle coordinates (24)
  Eigen::Vector3d impulse_Ns = Eigen::Vector3d::Zero();  // on the pole, (35), (36)
};

// The 3D impact map (see the header comment): the lower end sticks to a plate moving with
// plate_velocity_mps (the catching vehicle's velocity).
ImpactResult impact_map(const PoleState& before, const Eigen::Vector3d& plate_velocity_mps,
                        const PoleParams& params);

// The planar quantities of the header's convention for a pole flying in the xz-plane: alpha and
// alpha' of the direction n (from the end taken as the contact end to the centre) and the
// centre velocity (x', z'). Off the plane, alpha is taken from the projection of n on the
// xz-plane and alpha' = Omega_y.
struct PlanarPoleKinematics {
  double alpha_rad = 0.0;
  double alpha_dot_radps = 0.0;
  double x_dot_mps = 0.0;
  double z_dot_mps = 0.0;
};
// With the tail end p - L n as the contact end (alpha in (-pi, pi]).
PlanarPoleKinematics planar_kinematics(const PoleState& state);
// With the lower end as the contact end (|alpha| <= pi/2): planar_kinematics(with_lower_end_as_base()).
// Note that alpha jumps by pi when the pole passes the horizontal and the other end becomes the
// lower one; eq. (42) is continuous in time only between such instants.
PlanarPoleKinematics planar_kinematics_from_lower_end(const PoleState& state);

// alpha'+ for a plate at rest, eq. (40).
double post_impact_rate_radps(const PlanarPoleKinematics& before, const PoleParams& params);
// E* = m_p g L: the upright pole at rest on its pivot (left side of (41)).
double upright_energy_J(const PoleParams& params);
// The pole's energy on a pivot at rest, relative to the pivot (right side of (41)).
double pivoted_pole_energy_J(double alpha_rad, double alpha_dot_radps, const PoleParams& params);
// The rate on the separatrix branch that ends at the upright: -sqrt(3 g / L) sin(alpha / 2).
double swing_up_rate_radps(double alpha_rad, const PoleParams& params);
// This file's eq. (42): C = 4 (alpha'+ - swing_up_rate). Zero at the optimal catching instant.
double catching_condition_residual_radps(const PlanarPoleKinematics& before, const PoleParams& params);
// The same for a free-flying pole, with its lower end as the contact end.
double catching_condition_residual_radps(const PoleState& before, const PoleParams& params);

// (42) is planar. A pole flying in another vertical plane is judged in its own plane, turned onto
// the xz-plane: without the turn a throw along y has alpha ~ 0 and Omega_y ~ 0 in the xz-plane,
// and its "catching instant" is nonsense (measured: predicted 3.3 m below the floor, the catch
// retimed 0.5 m low and the pole dropped). The plane's yaw is that of its +x, the way the pole
// tips with Omega along +y: from the horizontal part of Omega, or, for a pole that hardly turns,
// from its centre's horizontal velocity (0 when neither says). Take it once per flight, from its
// first state, so that (42) stays continuous along the flight.
double flight_plane_yaw_rad(const PoleState& state);
// The state seen from a frame turned by yaw_rad about the vertical through the origin.
PoleState turned_by_yaw(const PoleState& state, double yaw_rad);

}  // namespace gs::model
