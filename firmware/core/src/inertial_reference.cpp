#include "fw/inertial_reference.hpp"

namespace fw {

// At rest the attitude estimate aligns up with the accelerometer's reading, bias b included, so
// it leans by b_perp / g: 0.4 m/s^2 of bias is 2.3 degrees, which the levelled failsafe would
// fly, drifting tens of metres and (the drag then seen along body z) stalling its descent. In
// flight the body x/y accelerometer reads only drag and that bias (the thrust is along body z),
// and the ground station holds the vehicle still on average: its mean is b_perp. The lean is
// fixed in the estimated inertial frame (the gyro carries it along), so it is removed there,
// once per failsafe, with the share of b_perp that the vertical bias learnt at rest took.
void InertialReference::correct_rest_tilt(AttitudeEstimator& attitude) {
  rest_tilt_corrected_ = true;
  constexpr float inv_g = 1.0f / pa::kGravityFloat_mps2;
  const Vec3f lean = AttitudeEstimator::rotate_to_inertial(
      rest_attitude_, Vec3f{flight_accel_x_mps2_ * inv_g, flight_accel_y_mps2_ * inv_g, 0.0f});
  attitude.correct_tilt(Vec3f{-lean[0], -lean[1], 1.0f});
  accel_bias_up_mps2_ -= 0.5f * pa::kGravityFloat_mps2 * (lean[0] * lean[0] + lean[1] * lean[1]);
}

}  // namespace fw
