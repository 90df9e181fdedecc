// Aerodynamic drag on the pole, the paper's law (eqs. (10)-(15)) integrated by a midpoint rule
// over segments along the pole. Each point at distance xi from the centre moves with
// v(xi) = v_p + omega x (xi n) (12); its velocity splits into the part along the pole and the
// part across it (13), (14), and each part is resisted in proportion to its speed squared with
// its own coefficient (c_z, c_xy). The torque uses the paper's separate rotational coefficient
// c_rot on the full point velocity (15). The axial part of the force and every term of the
// torque act through the pole's axis, so drag never spins the pole about its own axis.
#pragma once

#include "hil/plant/plant_config.hpp"
#include "hil/plant/types.hpp"

namespace hil {

struct Wrench {
  Vec3 force_N = Vec3::Zero();    // inertial frame
  Vec3 torque_Nm = Vec3::Zero();  // inertial frame, about the centre of mass
};

// velocity_mps: centre-of-mass velocity; rate_radps: angular velocity (inertial frame);
// axis: the unit vector n.
Wrench pole_drag(const PoleConfig& pole, const Vec3& velocity_mps, const Vec3& rate_radps, const Vec3& axis);

}  // namespace hil
