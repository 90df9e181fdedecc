// The balancing LQR for the pole on a vehicle (Section VII-A: "the infinite-horizon LQR
// controller from [7]"), designed on the pole-on-vehicle dynamics (30) linearised about the
// upright pole over a hovering vehicle.
//
// State s_qp (eq. (31)) = (x, y, z, vx, vy, vz, phi, theta, psi, a, b, a', b'), inputs
// u_q = (a_q, Omega_x, Omega_y, Omega_z); the equilibrium is a_q = g, everything else zero.
// The linearisation is taken numerically (central differences, linear_system.hpp) from
// gs::model::vehicle_pole_dynamics, so it follows the model wherever it goes. To first order it is
// the hover model (hover_lqr.hpp) plus, from (4/3) r'' = -f + ... (pole_on_vehicle.hpp) with
// f = a_q (theta, -phi, 1):
//   a'' = (3 g / 4 L) a - (3 g / 4) theta,   b'' = (3 g / 4 L) b + (3 g / 4) phi
// (in the plane: (4/3) L alpha'' = a_q sin(alpha - theta), a = L sin alpha); the tests check the
// numerical matrices against these.
#pragma once

#include <Eigen/Core>

#include "groundstation/control/lqr.hpp"
#include "groundstation/model/pole_on_vehicle.hpp"

namespace gs::control {

namespace balancing {
inline constexpr int kStateSize = 13;
inline constexpr int kInputSize = 4;
enum State : int { kX = 0, kY, kZ, kVx, kVy, kVz, kRoll, kPitch, kYaw, kA, kB, kADot, kBDot };
enum Input : int { kThrust = 0, kRateX, kRateY, kRateZ };
}  // namespace balancing

// s_qp as a vector in the order above, and back.
Eigen::VectorXd to_balancing_vector(const model::VehiclePoleState& state);
model::VehiclePoleState from_balancing_vector(const Eigen::VectorXd& x);
Eigen::VectorXd to_balancing_input(const model::VehicleInput& input);
model::VehicleInput from_balancing_input(const Eigen::VectorXd& u);

// Jacobians of (30) at the upright hover.
LinearSystem balancing_linearisation(const model::PoleParams& params = {});

// Q = diag(2, 2, 4 | 1, 1, 1 | 0.5, 0.5, 0.5 | 20, 20 | 2, 2)
//   on (x, y, z m | velocities m/s | phi, theta, psi rad | a, b m | a', b' m/s),
// R = diag(0.5 | 0.5, 0.5, 0.5) on (a_q m/s^2 | Omega rad/s).
// The pole deflection weighs most (20 m^-2: a 5 degree tilt, a = 0.058 m, costs as much as
// a 0.18 m position error), position errors least, so the vehicle gives up position to catch the
// pole first and walks back slowly. Checked (balancing_lqr_test) by a nonlinear planar simulation
// from 5 degrees and 0.2 m that stays within a_q in [1, 20] m/s^2 and |Omega| <= 10 rad/s.
LqrWeights balancing_lqr_weights();

LqrGain balancing_lqr(const LqrWeights& weights = balancing_lqr_weights(),
                      const model::PoleParams& params = {});

}  // namespace gs::control
