// The force between a point (a pole end with its shock absorber, a vehicle's foot) and a
// surface (a catching plate, the floor), as a compliant penalty contact:
//
//  - along the surface normal, a spring and a damper on the penetration depth that only push:
//    F_n = max(0, k depth + D(rate)), rate = d depth / dt. While the point sinks in, the damper
//    force saturates (D = F_max tanh(c rate / F_max)): the paper's shock absorber is a sliding
//    cap on a flour-filled balloon (Section VII-A), whose resistance does not grow without bound
//    with the impact speed; while it comes back out, the damper is linear and stronger
//    (D = c_rebound rate, negative), as the flour does not spring back. The impact is then
//    nearly inelastic - the paper's assumption - over 1-6 m/s, the contact lasts tens of
//    milliseconds and its peak stays moderate, which is what the IMU and the impact detector see;
//  - along the surface, a spring-damper pulling the point back to an anchor, the place where
//    it stuck; the force is capped at the Coulomb limit mu F_n, and when the spring alone would
//    exceed the limit, the anchor is dragged along (slip). A pole end resting on a plate is
//    thereby held in place without creep, and slides when the tilt asks for more than friction
//    can give.
#pragma once

#include "hil/plant/types.hpp"

namespace hil {

struct ContactLaw {
  double stiffness_Npm = 0.0;
  double damping_Nspm = 0.0;          // c, while sinking in (at small rates)
  double damping_force_max_N = 1.0;   // F_max: the sinking-in damper force saturates at this
  double rebound_damping_Nspm = 0.0;  // c_rebound, while coming back out
  double friction = 0.0;              // Coulomb coefficient mu
  double tangential_stiffness_Npm = 0.0;
  double tangential_damping_Nspm = 0.0;
};

// Normal force magnitude (>= 0) for a penetration depth (> 0 inside) and the normal component
// of the point's velocity relative to the surface (negative when sinking in).
double contact_normal_force_N(const ContactLaw& law, double depth_m, double normal_velocity_mps);

// The full force on the point (the surface receives the opposite). `normal` is the unit surface
// normal, `relative_velocity_mps` the point's velocity relative to the surface material there,
// `anchor_offset_m` the point's tangential displacement from its anchor (zero without one).
Vec3 contact_force_N(const ContactLaw& law, const Vec3& normal, double depth_m,
                     const Vec3& relative_velocity_mps, const Vec3& anchor_offset_m);

// The anchor offset after slipping: unchanged while the spring force stays within mu F_n,
// otherwise shortened along itself to the length at which it equals the limit.
Vec3 slipped_anchor_offset_m(const ContactLaw& law, double normal_force_N, const Vec3& anchor_offset_m);

}  // namespace hil
