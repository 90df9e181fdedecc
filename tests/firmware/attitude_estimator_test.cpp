// The complementary attitude filter used by the failsafe levelled hover.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "fw/attitude_estimator.hpp"
#include "pa/constants.hpp"

namespace {

using fw::AttitudeEstimator;
using fw::Vec3f;

constexpr float kG = pa::kGravityFloat_mps2;
constexpr float kDt_s = 0.001f;

// Specific force at rest: g times inertial up expressed in the body.
Vec3f rest_accel(const Vec3f& up_body) { return {kG * up_body[0], kG * up_body[1], kG * up_body[2]}; }

// Inertial up seen from a body rolled by phi (about x) or pitched by theta (about y).
Vec3f up_rolled(double phi) { return {0.0f, float(std::sin(phi)), float(std::cos(phi))}; }
Vec3f up_pitched(double theta) { return {float(-std::sin(theta)), 0.0f, float(std::cos(theta))}; }

Vec3f normalised(const Vec3f& v) {
  const double x = v[0], y = v[1], z = v[2];
  const double n = std::sqrt(x * x + y * y + z * z);
  return {float(x / n), float(y / n), float(z / n)};
}

// Angle between two unit vectors, rad.
double angle(const Vec3f& a, const Vec3f& b) {
  const double ax = a[0], ay = a[1], az = a[2], bx = b[0], by = b[1], bz = b[2];
  const double c = ax * bx + ay * by + az * bz;
  const double cx = ay * bz - az * by;
  const double cy = az * bx - ax * bz;
  const double cz = ax * by - ay * bx;
  return std::atan2(std::sqrt(cx * cx + cy * cy + cz * cz), c);
}

double quat_norm(const fw::Quaternion& q) {
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  return std::sqrt(w * w + x * x + y * y + z * z);
}

void run(AttitudeEstimator& est, const Vec3f& gyro, const Vec3f& accel, double duration_s) {
  const int n = int(duration_s / double(kDt_s) + 0.5);
  for (int k = 0; k < n; ++k) est.update(gyro, accel, kDt_s);
}

}  // namespace

TEST_CASE("attitude estimator: level at rest stays level") {
  AttitudeEstimator est;
  CHECK_FALSE(est.aligned());
  run(est, {0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, kG}, 10.0);
  CHECK(est.aligned());
  CHECK(est.tilt_cos() == Approx(1.0f).margin(1e-6));
  const auto& q = est.quaternion();
  CHECK(q[0] == Approx(1.0f).margin(1e-6));
  CHECK(quat_norm(q) == Approx(1.0).margin(1e-6));
}

TEST_CASE("attitude estimator: the first usable accelerometer sample aligns the tilt") {
  SECTION("tilted") {
    AttitudeEstimator est;
    const Vec3f accel{1.3f, -2.1f, 9.4f};
    est.update({0.0f, 0.0f, 0.0f}, accel, kDt_s);
    REQUIRE(est.aligned());
    CHECK(angle(est.up_in_body(), normalised(accel)) < 1e-5);
    CHECK(est.quaternion()[3] == Approx(0.0f).margin(1e-7));  // no yaw invented
  }
  SECTION("upside down") {
    AttitudeEstimator est;
    est.update({0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -kG}, kDt_s);
    CHECK(est.tilt_cos() == Approx(-1.0f).margin(1e-6));
  }
  SECTION("a sample outside the gravity gate does not align; the gyro integrates from level") {
    AttitudeEstimator est(0.0f);
    est.update({1.0f, 0.0f, 0.0f}, {0.0f, 5.0f, 25.0f}, 0.01f);  // a throw: |a| far from g
    CHECK_FALSE(est.aligned());
    CHECK(angle(est.up_in_body(), up_rolled(0.01)) < 1e-5);
    est.update({0.0f, 0.0f, 0.0f}, rest_accel(up_pitched(0.2)), kDt_s);
    CHECK(est.aligned());
    CHECK(angle(est.up_in_body(), up_pitched(0.2)) < 1e-5);
  }
  SECTION("reset_level returns to level and aligns again") {
    AttitudeEstimator est;
    est.update({0.0f, 0.0f, 0.0f}, rest_accel(up_rolled(0.5)), kDt_s);
    est.reset_level();
    CHECK_FALSE(est.aligned());
    CHECK(est.tilt_cos() == 1.0f);
    est.update({0.0f, 0.0f, 0.0f}, rest_accel(up_pitched(-0.3)), kDt_s);
    CHECK(angle(est.up_in_body(), up_pitched(-0.3)) < 1e-5);
  }
}

TEST_CASE("attitude estimator: a constant rotation integrates to the right angle") {
  SECTION("roll, gyro only") {
    AttitudeEstimator est(0.0f);
    est.update({}, {0.0f, 0.0f, kG}, kDt_s);  // align level
    run(est, {0.5f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, 2.0);
    CHECK(angle(est.up_in_body(), up_rolled(1.0)) < 1e-4);
    CHECK(est.tilt_cos() == Approx(std::cos(1.0)).margin(1e-4));
    const auto& q = est.quaternion();
    CHECK(q[0] == Approx(std::cos(0.5)).margin(1e-4));
    CHECK(q[1] == Approx(std::sin(0.5)).margin(1e-4));
  }
  SECTION("pitch, gyro only") {
    AttitudeEstimator est(0.0f);
    est.update({}, {0.0f, 0.0f, kG}, kDt_s);
    run(est, {0.0f, -0.8f, 0.0f}, {0.0f, 0.0f, 0.0f}, 1.0);
    CHECK(angle(est.up_in_body(), up_pitched(-0.8)) < 1e-4);
  }
  SECTION("yaw, three radians: tilt untouched, quaternion about z") {
    AttitudeEstimator est;
    est.update({}, {0.0f, 0.0f, kG}, kDt_s);
    run(est, {0.0f, 0.0f, 1.0f}, {0.0f, 0.0f, kG}, 3.0);
    const auto& q = est.quaternion();
    CHECK(est.tilt_cos() == Approx(1.0f).margin(1e-6));
    CHECK(q[0] == Approx(std::cos(1.5)).margin(1e-4));
    CHECK(q[3] == Approx(std::sin(1.5)).margin(1e-4));
  }
  SECTION("a full flip with the accelerometer gated out (as in free fall) returns to level") {
    AttitudeEstimator est;
    est.update({}, {0.0f, 0.0f, kG}, kDt_s);
    const double w = 2.0 * 3.14159265358979;  // one turn in one second
    run(est, {float(w), 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, 1.0);
    CHECK(est.tilt_cos() == Approx(1.0f).margin(1e-4));
    CHECK(quat_norm(est.quaternion()) == Approx(1.0).margin(1e-6));
  }
  SECTION("rolling with a consistent accelerometer follows the true attitude") {
    AttitudeEstimator est;
    est.update({}, {0.0f, 0.0f, kG}, kDt_s);
    for (int k = 1; k <= 2000; ++k) {
      const double phi = 0.5 * k * double(kDt_s);
      est.update({0.5f, 0.0f, 0.0f}, rest_accel(up_rolled(phi)), kDt_s);
    }
    CHECK(angle(est.up_in_body(), up_rolled(1.0)) < 1e-4);
  }
}

TEST_CASE("attitude estimator: a misinitialised estimate converges to the accelerometer's tilt") {
  AttitudeEstimator est;                    // default gain 2 / s
  est.update({}, {0.0f, 0.0f, kG}, kDt_s);  // believes it is level
  const Vec3f up_true = normalised({0.3f, -0.4f, 1.0f});
  const double err0 = angle(est.up_in_body(), up_true);
  // Small gain: a single sample barely moves it (a throw or a bump cannot flip the estimate) ...
  run(est, {}, rest_accel(up_true), 0.1);
  CHECK(angle(est.up_in_body(), up_true) > 0.7 * err0);
  // ... but it converges at about the gain: exp(-2 * 5) of the initial error after 5 s.
  run(est, {}, rest_accel(up_true), 4.9);
  CHECK(angle(est.up_in_body(), up_true) < 1e-3);
}

TEST_CASE("attitude estimator: a gyro bias leaves only a bounded tilt error") {
  const Vec3f bias{0.02f, -0.01f, 0.0f};
  const double bias_radps = std::sqrt(0.02 * 0.02 + 0.01 * 0.01);
  const Vec3f level{0.0f, 0.0f, kG};

  AttitudeEstimator est;  // gain 2 / s
  est.update({}, level, kDt_s);
  run(est, bias, level, 20.0);
  const double err = angle(est.up_in_body(), {0.0f, 0.0f, 1.0f});
  // Steady state: the correction rate k sin(err) balances the bias.
  CHECK(err == Approx(bias_radps / 2.0).epsilon(0.05));

  AttitudeEstimator gyro_only(0.0f);
  gyro_only.update({}, level, kDt_s);
  run(gyro_only, bias, level, 20.0);
  CHECK(angle(gyro_only.up_in_body(), {0.0f, 0.0f, 1.0f}) == Approx(20.0 * bias_radps).epsilon(0.01));
}

TEST_CASE("attitude estimator: the correction is skipped when |accel| is far from g") {
  AttitudeEstimator est;
  est.update({}, {0.0f, 0.0f, kG}, kDt_s);
  // An impact: a huge tilted specific force for a while must not move the estimate.
  run(est, {}, {30.0f, 0.0f, 30.0f}, 0.5);
  CHECK(est.tilt_cos() == Approx(1.0f).margin(1e-6));
  // Near free fall likewise.
  run(est, {}, {0.5f, 0.5f, 0.5f}, 0.5);
  CHECK(est.tilt_cos() == Approx(1.0f).margin(1e-6));
  // Just inside the gate it corrects.
  const float inside = (1.0f - 0.9f * AttitudeEstimator::kAccelGateFraction) * kG;
  run(est, {}, {inside * 0.6f, 0.0f, inside * 0.8f}, 0.5);
  CHECK(est.tilt_cos() < 0.99f);
}

TEST_CASE("attitude estimator: non-finite input is ignored") {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  AttitudeEstimator est(0.0f);
  est.update({}, rest_accel(up_rolled(0.2)), kDt_s);
  const fw::Quaternion before = est.quaternion();

  est.update({nan, 0.0f, 0.0f}, {0.0f, 0.0f, kG}, kDt_s);
  est.update({0.0f, inf, 0.0f}, {0.0f, 0.0f, kG}, kDt_s);
  est.update({1.0f, 0.0f, 0.0f}, {0.0f, 0.0f, kG}, nan);
  est.update({1.0f, 0.0f, 0.0f}, {0.0f, 0.0f, kG}, -inf);
  for (int i = 0; i < 4; ++i) CHECK(est.quaternion()[i] == before[i]);

  // A bad accelerometer alone only skips the correction: the gyro still integrates.
  AttitudeEstimator with_gain;
  with_gain.update({}, {0.0f, 0.0f, kG}, kDt_s);
  run(with_gain, {0.5f, 0.0f, 0.0f}, {nan, 0.0f, kG}, 1.0);
  CHECK(angle(with_gain.up_in_body(), up_rolled(0.5)) < 1e-4);

  // ... and cannot align a fresh estimator.
  AttitudeEstimator fresh;
  fresh.update({}, {0.0f, inf, kG}, kDt_s);
  CHECK_FALSE(fresh.aligned());
  CHECK(fresh.tilt_cos() == 1.0f);
}

TEST_CASE("attitude estimator: dt is clamped into [0, kDtMax_s]") {
  const auto roll_after = [](float dt_s) {
    AttitudeEstimator est(0.0f);
    est.update({}, {0.0f, 0.0f, kG}, kDt_s);
    est.update({1.0f, 0.0f, 0.0f}, {}, dt_s);
    return angle(est.up_in_body(), {0.0f, 0.0f, 1.0f});
  };
  CHECK(roll_after(0.004f) == Approx(0.004).margin(1e-6));
  CHECK(roll_after(-0.01f) == Approx(0.0).margin(1e-7));
  CHECK(roll_after(5.0f) == Approx(AttitudeEstimator::kDtMax_s).margin(1e-6));
  CHECK(roll_after(1e30f) == Approx(AttitudeEstimator::kDtMax_s).margin(1e-6));
}

TEST_CASE("attitude estimator: gains that make no sense fall back to gyro integration") {
  for (float gain : {-1.0f, std::numeric_limits<float>::quiet_NaN()}) {
    AttitudeEstimator est(gain);
    est.update({}, {0.0f, 0.0f, kG}, kDt_s);
    run(est, {}, rest_accel(up_rolled(0.3)), 2.0);
    CHECK(est.tilt_cos() == Approx(1.0f).margin(1e-6));
  }
}

TEST_CASE("attitude estimator: a tilt error known from elsewhere is removed in the inertial frame") {
  // At rest the estimate aligns with an accelerometer biased along body x: it leans by b / g.
  const float bias_mps2 = 0.4f;
  AttitudeEstimator est;
  run(est, {}, {bias_mps2, 0.0f, kG}, 5.0);
  const double lean = std::atan2(bias_mps2, kG);
  REQUIRE(angle(est.up_in_body(), {0.0f, 0.0f, 1.0f}) == Approx(lean).epsilon(1e-3));
  // Then in flight (gyro only) the vehicle turns a quarter about up: the lean stays fixed in the
  // estimated inertial frame, not in the body.
  est.set_accel_gain(0.0f);
  const fw::Quaternion rest = est.quaternion();
  run(est, {0.0f, 0.0f, float(M_PI / 2.0)}, {0.0f, 0.0f, kG}, 1.0);
  // The correction computed from the rest attitude and the bias puts up back on body z.
  const Vec3f lean_inertial = AttitudeEstimator::rotate_to_inertial(rest, {bias_mps2 / kG, 0.0f, 0.0f});
  est.correct_tilt({-lean_inertial[0], -lean_inertial[1], 1.0f});
  CHECK(angle(est.up_in_body(), {0.0f, 0.0f, 1.0f}) < 2e-3 * lean);
  CHECK(quat_norm(est.quaternion()) == Approx(1.0).margin(1e-6));
  SECTION("the yaw is kept") {
    const Vec3f forward = est.to_inertial({1.0f, 0.0f, 0.0f});
    CHECK(std::atan2(forward[1], forward[0]) == Approx(M_PI / 2.0).margin(5e-3));
  }
  SECTION("a vector that is not finite or points down changes nothing") {
    const fw::Quaternion before = est.quaternion();
    est.correct_tilt({0.1f, 0.0f, -1.0f});
    est.correct_tilt({std::numeric_limits<float>::quiet_NaN(), 0.0f, 1.0f});
    est.correct_tilt({0.0f, 0.0f, 0.0f});
    CHECK(est.quaternion() == before);
  }
}
