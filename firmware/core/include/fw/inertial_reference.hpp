// What the vehicle knows of its own motion without motion capture, for the failsafe to start
// from: the accelerometer's bias along up and the gyro's bias, learnt at rest on the floor; the
// vertical speed, integrated in flight with a leak; and the tilt the attitude estimate took at
// rest from the accelerometer's x/y bias, removed once per failsafe. The per-tick and per-task
// members are inline (the loop pays no call for them). No heap.
#pragma once

#include <cmath>
#include <cstdint>

#include "fw/attitude_estimator.hpp"
#include "fw/types.hpp"
#include "pa/constants.hpp"

namespace fw {

class InertialReference {
 public:
  // The biases are learnt from samples this still and this close to g (a vehicle being carried
  // or bumped is not at rest), averaged over up to kBiasWindow samples.
  static constexpr float kBiasStillRate2_radps2 = 0.1f * 0.1f;
  static constexpr float kBiasMax_mps2 = 0.5f;
  static constexpr float kBiasWindow = 2000.0f;
  // track_flight() runs every kTrackPeriod_ticks ticks of the 1 kHz loop.
  static constexpr std::uint32_t kTrackPeriod_ticks = 5;
  static constexpr float kTrackPeriod_s = kTrackPeriod_ticks * 0.001f;
  // The vertical speed forgets with this time constant: it bounds the drift from the
  // accelerometer's residual bias over a long flight (the ground station holds the vehicle still
  // on average), and costs climb / constant (0.06 m/s after a 3.5 m climb).
  static constexpr float kFlightVzLeak_s = 60.0f;
  // The mean of the body x/y accelerometer in flight (its bias) over this time constant: long
  // against the drag of a manoeuvre, short against the hover before a throw.
  static constexpr float kFlightAccelMean_s = 2.0f;

  static float dot(const Vec3f& a, const Vec3f& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

  // One sample at rest on the floor. There the accelerometer reads g exactly, so what it reads
  // more is its bias (along up: the x and y biases only tilt the measured up, second order in its
  // length). The failsafe integrates its vertical speed from the accelerometer; without this the
  // speed drifted by bias * time, from 4.9 m enough to stall the descent and climb.
  void learn_at_rest(const Vec3f& gyro_radps, const Vec3f& accel_mps2) {
    if (dot(gyro_radps, gyro_radps) > kBiasStillRate2_radps2) return;
    const float excess_mps2 = std::sqrt(dot(accel_mps2, accel_mps2)) - pa::kGravityFloat_mps2;
    if (std::fabs(excess_mps2) > kBiasMax_mps2) return;
    if (bias_samples_ < kBiasWindow) bias_samples_ += 1.0f;
    accel_bias_up_mps2_ += (excess_mps2 - accel_bias_up_mps2_) / bias_samples_;
    // At rest the gyro reads its bias (the Earth's rate, 7e-5 rad/s, is below its noise).
    for (int i = 0; i < 3; ++i) gyro_bias_radps_[i] += (gyro_radps[i] - gyro_bias_radps_[i]) / bias_samples_;
  }
  Vec3f unbiased_rate_radps(const Vec3f& gyro_radps) const {
    return Vec3f{gyro_radps[0] - gyro_bias_radps_[0], gyro_radps[1] - gyro_bias_radps_[1],
                 gyro_radps[2] - gyro_bias_radps_[2]};
  }
  // The specific force along the estimated up, less the bias learnt at rest.
  float up_accel_mps2(const Vec3f& accel_mps2, const Vec3f& up_in_body) const {
    return dot(accel_mps2, up_in_body) - accel_bias_up_mps2_;
  }

  // On the floor (or killed): nothing moves; the attitude at rest is kept for correct_rest_tilt.
  void rest(const Quaternion& attitude) {
    flight_vz_mps_ = 0;
    flight_accel_x_mps2_ = flight_accel_y_mps2_ = 0;
    rest_attitude_ = attitude;
    rest_tilt_corrected_ = false;
  }
  // In flight, every kTrackPeriod_ticks: a cut stream can find the vehicle moving (a catch
  // manoeuvre descends, a throw climbs), so the failsafe starts from the speed integrated here.
  void track_flight(float up_accel_mps2, const Vec3f& accel_mps2) {
    constexpr float h = kTrackPeriod_s;
    flight_vz_mps_ += (up_accel_mps2 - pa::kGravityFloat_mps2 - flight_vz_mps_ / kFlightVzLeak_s) * h;
    constexpr float a = h / kFlightAccelMean_s;
    flight_accel_x_mps2_ += (accel_mps2[0] - flight_accel_x_mps2_) * a;
    flight_accel_y_mps2_ += (accel_mps2[1] - flight_accel_y_mps2_) * a;
  }
  // In on-board flight the failsafe's speed is the estimate: a failsafe the ground station ends
  // goes on from there.
  void follow_vz(float vz_mps) { flight_vz_mps_ = vz_mps; }

  // Once per failsafe (rest_tilt_corrected() is false until the next rest).
  bool rest_tilt_corrected() const { return rest_tilt_corrected_; }
  // Motion capture has set the tilt in flight (COMMAND correct_tilt): the lean taken at rest is
  // gone with the rest of the error.
  void tilt_corrected() { rest_tilt_corrected_ = true; }
  void correct_rest_tilt(AttitudeEstimator& attitude);

  float accel_bias_up_mps2() const { return accel_bias_up_mps2_; }
  const Vec3f& gyro_bias_radps() const { return gyro_bias_radps_; }
  float flight_vz_mps() const { return flight_vz_mps_; }

 private:
  float accel_bias_up_mps2_ = 0;
  float bias_samples_ = 0;
  Vec3f gyro_bias_radps_{};
  float flight_vz_mps_ = 0;
  // The attitude at rest's last periodic sample, and the bias as the mean body x/y reading in
  // flight.
  Quaternion rest_attitude_{1.0f, 0.0f, 0.0f, 0.0f};
  float flight_accel_x_mps2_ = 0;
  float flight_accel_y_mps2_ = 0;
  bool rest_tilt_corrected_ = false;
};

}  // namespace fw
