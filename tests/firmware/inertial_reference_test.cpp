// What the failsafe starts from: the biases learnt at rest, the vertical speed in flight, the
// tilt taken at rest from the accelerometer's bias.
#include <catch2/catch.hpp>

#include <cmath>

#include "fw/attitude_estimator.hpp"
#include "fw/inertial_reference.hpp"
#include "pa/constants.hpp"

namespace {

using fw::InertialReference;
using fw::Vec3f;

constexpr float kG = pa::kGravityFloat_mps2;
const Vec3f kLevel{0.0f, 0.0f, 1.0f};

}  // namespace

TEST_CASE("the biases are learnt from still samples near g, a running mean over the window") {
  InertialReference r;
  const Vec3f gyro_bias{0.01f, -0.02f, 0.005f};
  for (int i = 0; i < 100; ++i) r.learn_at_rest(gyro_bias, Vec3f{0.0f, 0.0f, kG + 0.2f});
  CHECK(r.accel_bias_up_mps2() == Approx(0.2f).epsilon(1e-3));
  CHECK(r.gyro_bias_radps()[1] == Approx(-0.02f).epsilon(1e-4));
  const Vec3f rate = r.unbiased_rate_radps(Vec3f{1.0f, 1.0f, 1.0f});
  CHECK(rate[0] == Approx(0.99f));
  CHECK(rate[1] == Approx(1.02f));
  // Carried (turning) or bumped (far from g): not at rest, nothing learnt.
  r.learn_at_rest(Vec3f{0.2f, 0.0f, 0.0f}, Vec3f{0.0f, 0.0f, kG + 0.4f});
  r.learn_at_rest(gyro_bias, Vec3f{0.0f, 0.0f, kG + 0.6f});
  CHECK(r.accel_bias_up_mps2() == Approx(0.2f).epsilon(1e-3));
  // Past the window a new bias comes in at 1 / kBiasWindow per sample.
  for (int i = 0; i < 4000; ++i) r.learn_at_rest(gyro_bias, Vec3f{0.0f, 0.0f, kG + 0.2f});
  r.learn_at_rest(gyro_bias, Vec3f{0.0f, 0.0f, kG});
  CHECK(r.accel_bias_up_mps2() == Approx(0.2f - 0.2f / InertialReference::kBiasWindow).epsilon(1e-4));
  // The specific force along up, less the bias.
  CHECK(r.up_accel_mps2(Vec3f{1.0f, 0.0f, kG + 0.2f}, kLevel) == Approx(kG).epsilon(1e-4));
}

TEST_CASE("the vertical speed in flight integrates the unbiased specific force and forgets slowly") {
  InertialReference r;
  const int per_s = static_cast<int>(1.0f / InertialReference::kTrackPeriod_s + 0.5f);
  for (int i = 0; i < per_s; ++i) r.track_flight(kG, Vec3f{0.0f, 0.0f, kG});
  CHECK(r.flight_vz_mps() == 0.0f);
  for (int i = 0; i < per_s; ++i) r.track_flight(kG + 1.0f, Vec3f{0.0f, 0.0f, kG + 1.0f});
  const float leak = InertialReference::kFlightVzLeak_s;
  CHECK(r.flight_vz_mps() == Approx(leak * (1.0f - std::exp(-1.0f / leak))).epsilon(1e-3));
  // From 1 m/s with no acceleration it decays with the leak's time constant.
  r.follow_vz(1.0f);
  for (int i = 0; i < static_cast<int>(leak) * per_s; ++i) r.track_flight(kG, Vec3f{0.0f, 0.0f, kG});
  CHECK(r.flight_vz_mps() == Approx(std::exp(-1.0f)).epsilon(2e-3));
  r.rest(fw::Quaternion{1.0f, 0.0f, 0.0f, 0.0f});
  CHECK(r.flight_vz_mps() == 0.0f);
}

TEST_CASE("the tilt taken at rest from the accelerometer's x/y bias is removed once per failsafe") {
  const float bias_x_mps2 = 0.4f;  // 2.3 degrees of lean
  const Vec3f reading{bias_x_mps2, 0.0f, kG};
  fw::AttitudeEstimator attitude;
  attitude.update(Vec3f{}, reading, 0.001f);  // aligns to the reading, bias included
  const float lean = std::fabs(attitude.up_in_body()[0]);
  CHECK(lean == Approx(bias_x_mps2 / kG).epsilon(0.01));

  InertialReference r;
  r.learn_at_rest(Vec3f{}, reading);
  const float bias_up = r.accel_bias_up_mps2();
  r.rest(attitude.quaternion());
  CHECK_FALSE(r.rest_tilt_corrected());
  // In flight the body x/y accelerometer reads its bias (and drag, zero on average).
  const int per_s = static_cast<int>(1.0f / InertialReference::kTrackPeriod_s + 0.5f);
  for (int i = 0; i < 20 * per_s; ++i) r.track_flight(kG, reading);
  r.correct_rest_tilt(attitude);
  CHECK(r.rest_tilt_corrected());
  CHECK(std::fabs(attitude.up_in_body()[0]) < 0.05f * lean);
  CHECK(attitude.up_in_body()[2] == Approx(1.0f).margin(1e-5));
  // The share of the bias the vertical estimate took at rest is given back.
  CHECK(bias_up - r.accel_bias_up_mps2() == Approx(0.5f * bias_x_mps2 * bias_x_mps2 / kG).epsilon(0.02));
  r.rest(attitude.quaternion());
  CHECK_FALSE(r.rest_tilt_corrected());
}
