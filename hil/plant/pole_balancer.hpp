// A balancing law for the scenario runner (a test-data generator, like vehicle_controller.hpp):
// from the TRUE states of the pole and of the vehicle whose plate holds its lower end, the
// horizontal acceleration of the vehicle that keeps the pole upright and brings the vehicle
// back to a reference position.
//
// Per horizontal axis, with alpha the tilt of the pole (from its supported end towards its
// centre) from the vertical, the rod of half length L pivoting at its end on a base with
// acceleration u obeys (4/3) L alpha'' = g sin(alpha) - u cos(alpha) (the pivot's inertial
// force acting at the centre of mass, moment of inertia 4 m L^2 / 3 about the end). Linearised
// with x the base position: x'' = u, alpha'' = a alpha - b u, with a = 3 g / (4 L), b = 3 / (4 L).
// The state feedback u = -(k1 x + k2 x' + k3 alpha + k4 alpha') gives the characteristic
// polynomial s^4 + (k2 - b k4) s^3 + (k1 - a - b k3) s^2 - a k2 s - a k1; the gains below put all
// four roots at -lambda.
#pragma once

#include "hil/plant/types.hpp"

namespace hil {

struct BalancerGains {
  double k_position = 0.0;   // k1, 1/s^2
  double k_velocity = 0.0;   // k2, 1/s
  double k_tilt = 0.0;       // k3, m/s^2 per rad
  double k_tilt_rate = 0.0;  // k4, m/s^2 per rad/s
};

// The gains that place every closed-loop root at -lambda_radps.
BalancerGains balancer_gains(double half_length_m, double gravity_mps2, double lambda_radps);

// The horizontal acceleration demand (z = 0). `supported_end` is the pole end resting on the
// vehicle's plate (0 or 1).
Vec3 balance_acceleration(const BalancerGains& gains, const PoleState& pole, int supported_end,
                          const VehicleState& vehicle, const Vec3& reference_m);

}  // namespace hil
