// The rotors of an X quadrocopter: each motor's thrust follows its command through a
// first-order lag, and the four thrusts give a force along body z and a torque.
//
// Geometry (firmware/core/include/fw/mixer.hpp order), a = arm_length / sqrt(2):
//   0 front-right (+a, -a)  spins counter-clockwise seen from above
//   1 rear-left   (-a, +a)  counter-clockwise
//   2 front-left  (+a, +a)  clockwise
//   3 rear-right  (-a, -a)  clockwise
// A rotor spinning counter-clockwise drags the airframe clockwise: yaw torque -k f about +z;
// a clockwise one gives +k f (k = yaw_moment_per_thrust_m).
#pragma once

#include <array>

#include "hil/plant/plant_config.hpp"
#include "hil/plant/types.hpp"

namespace hil {

// The thrust a motor settles at for a command: clamp(command, 0, 1) * gain * thrust_max; a
// non-finite command gives 0 (the ESC stops).
double motor_target_thrust_N(double command, double gain, double thrust_max_N);

// The thrust `elapsed_s` after a moment at which it was `thrust_N`, with the command held:
// the exact solution of tau df/dt = target - f (f = target when tau is 0). Being exact, it is
// stable for any step and never leaves the interval between the start and the target.
double motor_thrust_after_N(double thrust_N, double target_N, double time_constant_s, double elapsed_s);

// Motor i's position in the body frame (in the rotor plane through the CG).
Vec3 motor_position_body_m(const VehicleConfig& vehicle, int motor);
// +1 for a clockwise rotor (positive yaw reaction), -1 for a counter-clockwise one.
double motor_yaw_sign(int motor);

struct BodyWrench {
  Vec3 force_N = Vec3::Zero();    // body frame
  Vec3 torque_Nm = Vec3::Zero();  // body frame, about the CG
};

// Force and torque of the four rotors producing `thrust_N`.
BodyWrench rotor_wrench(const VehicleConfig& vehicle, const std::array<double, 4>& thrust_N);

}  // namespace hil
