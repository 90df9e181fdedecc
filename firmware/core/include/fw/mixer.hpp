// Control allocation for an X quadrocopter: collective thrust and body torques to motor thrusts.
//
// Body frame (the paper's vehicle frame B, Section II-A): x forward, y left, z up; thrust acts
// along +z (eq. (4)). Torques and rates are positive by the right-hand rule about these axes,
// so positive roll lifts the left side, positive pitch lowers the nose and positive yaw turns
// the nose left (counter-clockwise seen from above).
//
// Motor order and spin (PX4 quad-x order), each motor at arm_length_m on a diagonal:
//   0 front-right (+a, -a)  counter-clockwise seen from above
//   1 rear-left   (-a, +a)  counter-clockwise
//   2 front-left  (+a, +a)  clockwise
//   3 rear-right  (-a, -a)  clockwise
// with a = arm_length_m / sqrt(2). A rotor spinning counter-clockwise drags the body clockwise,
// i.e. gives yaw torque -yaw_moment_per_thrust_m * thrust, and a clockwise one +k * thrust.
//
//   thrust  = f0 + f1 + f2 + f3
//   roll    = a (-f0 + f1 + f2 - f3)
//   pitch   = a (-f0 + f1 - f2 + f3)
//   yaw     = k (-f0 - f1 + f2 + f3)
//
// Saturation priority: roll and pitch first, then collective, then yaw. Everything the motors
// cannot deliver is reported, per axis and direction in `saturation` (fw::saturation bits, which
// the rate controller uses to stop its integrators winding up) and as amounts in the
// `*_unallocated_*` fields.
#pragma once

#include <array>
#include <cstdint>

#include "fw/config.hpp"
#include "fw/types.hpp"

namespace fw {

struct MixerInput {
  float thrust_N = 0.0f;  // collective thrust along body +z
  Vec3f torque_Nm{};      // body torques about x, y, z
};

struct MixerOutput {
  Motors thrust_N{};                  // per motor, always within [motor_thrust_min_N, the ceiling]
  Motors command{};                   // thrust_N / the ceiling (set_command_factor): normalised
  std::uint8_t saturation = 0;        // fw::saturation bits: what could not be allocated, by direction
  Vec3f torque_unallocated_Nm{};      // requested minus achieved torque
  float thrust_unallocated_N = 0.0f;  // requested minus achieved collective thrust
};

class Mixer {
 public:
  // Per-motor signs of each axis, in the motor order above.
  static constexpr std::array<float, 4> kRollSign{-1.0f, 1.0f, 1.0f, -1.0f};
  static constexpr std::array<float, 4> kPitchSign{-1.0f, 1.0f, -1.0f, 1.0f};
  static constexpr std::array<float, 4> kYawSign{-1.0f, -1.0f, 1.0f, 1.0f};

  // Requests beyond this magnitude are clipped before allocation so that no intermediate
  // overflows; the unallocated amounts are still reported against the original request.
  static constexpr float kRequestLimit = 1.0e9f;

  // The configuration is usable when every field is finite, arm_length_m > 0,
  // yaw_moment_per_thrust_m > 0 and 0 <= motor_thrust_min_N < motor_thrust_max_N.
  explicit Mixer(const AirframeConfig& airframe);

  bool valid() const { return valid_; }

  // Allocates the request in the priority order above.
  // A non-finite request puts every motor at motor_thrust_min_N (armed idle) and sets every
  // saturation bit (collective_high and collective_low together only ever mean "rejected");
  // the unallocated amounts are then zero, as there is no valid request to measure them against.
  // With an unusable configuration every motor gets zero thrust and every bit is set.
  MixerOutput mix(const MixerInput& input) const;

  // The collective thrust and torques that the given motor thrusts produce (the equations above).
  MixerInput effect(const Motors& thrust_N) const;

  // The battery's compensation (fw/battery_compensation.hpp): with the pack at V a motor makes
  // at most motor_thrust_max_N / factor, factor = (V_ref / V)^2, so the motor thrusts are
  // allocated under that ceiling and each command is thrust / ceiling, i.e. the thrust fraction
  // at V_ref times the factor; saturation keeps the priority above against the lower ceiling.
  // A factor that is not finite, not positive or that would put the ceiling at or below
  // motor_thrust_min_N is refused (false) and the previous one kept. Initially 1 (exactly the
  // allocation without it).
  bool set_command_factor(float factor);
  float thrust_ceiling_N() const { return thrust_ceiling_N_; }

 private:
  MixerOutput rejected(float motor_thrust_N) const;

  bool valid_ = false;
  float half_span_m_ = 0.0f;   // a: lever arm of each motor about x and y
  float yaw_moment_m_ = 0.0f;  // k
  float inv_4a_per_m_ = 0.0f;  // 1 / (4 a)
  float inv_4k_per_m_ = 0.0f;  // 1 / (4 k)
  float thrust_min_N_ = 0.0f;
  float thrust_max_N_ = 0.0f;
  float thrust_ceiling_N_ = 0.0f;  // thrust_max_N_ / the battery's factor
};

}  // namespace fw
