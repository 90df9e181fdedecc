// The on-board flight law of a hold and a failsafe, flown with no motion capture: level the
// vehicle, hold (or sink at) the vertical speed integrated from the accelerometer since it began,
// and detect the floor's support that ends the descent. Per-tick members are inline: they run in
// the failsafe's ticks, the firmware's heaviest. No heap.
#pragma once

#include "fw/config.hpp"
#include "fw/types.hpp"
#include "pa/constants.hpp"

namespace fw {

class FailsafeController {
 public:
  static constexpr float kVerticalGain_per_s = 4.0f;  // the vertical-speed loop's bandwidth
  static constexpr float kMinTiltCos = 0.5f;          // thrust compensation for tilt stops at 60 degrees
  static constexpr float kDtMax_s = 0.005f;           // a longer step is integrated as this one

  explicit FailsafeController(const SupervisorConfig& config);

  // Levelling law: body rates that turn the measured "up" towards the body z-axis.
  // For an inertial vector seen from the body, u' = -w x u; with w = k (e_z x u) the tilt decays.
  Vec3f levelling_rates(const Vec3f& up_in_body) const {
    const float k = level_gain_per_s_;
    return Vec3f{-k * up_in_body[1], k * up_in_body[0], 0.0f};
  }

  // On-board flight begins: from the vertical speed estimated in flight, on no ground yet.
  void start(float vz_mps) {
    vz_mps_ = vz_mps;
    ground_contact_s_ = 0;
  }
  // A touchdown's contact is over: the vehicle rests on the floor, so the speed integrated since
  // the start (which drifts with the accelerometer's bias) restarts from zero.
  void on_touchdown() { vz_mps_ = 0; }
  // Only the descent meets the floor.
  void clear_ground_contact() { ground_contact_s_ = 0; }

  // One tick of the vertical speed: `specific_up_mps2` is the specific force along the estimated
  // up, the accelerometer's bias removed.
  void integrate(float specific_up_mps2, float dt_s) {
    const float clamped_dt = dt_s < 0 ? 0 : (dt_s > kDtMax_s ? kDtMax_s : dt_s);
    vz_mps_ += (specific_up_mps2 - pa::kGravityFloat_mps2) * clamped_dt;
  }
  // The levelled hover's collective thrust: hold the vertical speed at zero.
  float hover_thrust_mps2(const Vec3f& up_in_body) const {
    return (pa::kGravityFloat_mps2 + kVerticalGain_per_s * (0.0f - vz_mps_)) / tilt_cos(up_in_body);
  }
  // The descent's collective thrust (sink at descent_rate_mps), and the ground contact: the floor
  // holds the vehicle up although the thrust applied last tick asks it to sink.
  float descend(const Vec3f& up_in_body, float specific_up_mps2, float thrust_applied_mps2, float dt_s) {
    const float target = -descent_rate_mps_;
    float thrust_mps2 =
        (pa::kGravityFloat_mps2 + kVerticalGain_per_s * (target - vz_mps_)) / tilt_cos(up_in_body);
    if (thrust_mps2 < 0) thrust_mps2 = 0;
    const float support = specific_up_mps2 - thrust_applied_mps2;
    if (support > ground_contact_mps2_) ground_contact_s_ += dt_s > 0 ? dt_s : 0;
    else ground_contact_s_ = 0;
    return thrust_mps2;
  }

  // The floor has held the vehicle up for ground_contact_us.
  bool on_ground() const { return ground_contact_s_ * 1e6f >= ground_contact_us_; }
  float vz_mps() const { return vz_mps_; }

 private:
  static float tilt_cos(const Vec3f& up_in_body) {
    return up_in_body[2] < kMinTiltCos ? kMinTiltCos : up_in_body[2];
  }

  float level_gain_per_s_;
  float descent_rate_mps_;
  float ground_contact_mps2_;
  float ground_contact_us_;  // config.ground_contact_us, as the float it is compared in
  float vz_mps_ = 0;
  float ground_contact_s_ = 0;
};

}  // namespace fw
