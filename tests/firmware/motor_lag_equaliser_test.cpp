// The motor-lag equaliser: with the motors' lag identified, the thrust follows the request through
// the airframe's design lag; with the design lag it changes nothing; bad lags and requests are
// refused without disturbing it.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "fw/motor_lag_equaliser.hpp"

namespace {

using fw::MixerInput;
using fw::MotorLagEqualiser;

constexpr float kDesign_s = 0.03f;
constexpr float kDt_s = 0.001f;

// A first-order lag stepped like the plant's motors (exact discretisation).
struct Lag {
  float tau_s;
  float y;
  float step(float u) { return y += (u - y) * (1.0f - std::exp(-kDt_s / tau_s)); }
};

// The request as the equaliser passes it on.
MixerInput equalised(MotorLagEqualiser& eq, MixerInput u, float dt_s) {
  eq.equalise(u, dt_s);
  return u;
}

MixerInput request(float thrust_N, float torque_x_Nm = 0.0f) {
  return MixerInput{thrust_N, {torque_x_Nm, 0.0f, 0.0f}};
}

// The largest difference between the thrust of motors lagging `motor_s`, driven through the
// equaliser set to `identified_s`, and the thrust of design-lag motors driven by the request
// itself, over a hover then a 2 N step held for 0.3 s.
float worst_mismatch_N(float motor_s, float identified_s) {
  MotorLagEqualiser eq(kDesign_s);
  REQUIRE(eq.set_motor_time_constant(identified_s));
  Lag motors{motor_s, 5.0f};
  Lag design{kDesign_s, 5.0f};
  float worst = 0.0f;
  for (int k = 0; k < 400; ++k) {
    const float u = k < 100 ? 5.0f : 7.0f;
    const float delivered = motors.step(equalised(eq, request(u), kDt_s).thrust_N);
    worst = std::fmax(worst, std::fabs(delivered - design.step(u)));
  }
  return worst;
}

}  // namespace

TEST_CASE("with the design lag the request passes bit for bit") {
  MotorLagEqualiser eq(kDesign_s);
  for (int k = 0; k < 50; ++k) {
    const MixerInput u = request(5.0f + 0.1f * static_cast<float>(k), 0.01f * static_cast<float>(k % 7));
    const MixerInput y = equalised(eq, u, kDt_s);
    CHECK(y.thrust_N == u.thrust_N);
    CHECK(y.torque_Nm[0] == u.torque_Nm[0]);
  }
  CHECK(eq.motor_time_constant_s() == kDesign_s);
}

TEST_CASE("slow or fast motors, equalised, deliver the design lag's thrust") {
  const float uncorrected = worst_mismatch_N(0.06f, kDesign_s);
  CHECK(uncorrected > 0.4f);  // 60 ms motors behind the design's 30 ms, by a third of the step
  CHECK(worst_mismatch_N(0.06f, 0.06f) < 0.02f);
  CHECK(worst_mismatch_N(0.05f, 0.05f) < 0.02f);
  CHECK(worst_mismatch_N(0.02f, 0.02f) < 0.02f);
  // Identified 10 % off, most of the mismatch is still gone.
  CHECK(worst_mismatch_N(0.06f, 0.054f) < 0.3f * uncorrected);
  CHECK(worst_mismatch_N(0.06f, 0.066f) < 0.3f * uncorrected);
}

TEST_CASE("the torques are equalised like the thrust") {
  MotorLagEqualiser eq(kDesign_s);
  REQUIRE(eq.set_motor_time_constant(0.06f));
  equalised(eq, request(5.0f, 0.0f), kDt_s);
  // A step leads by tau_m / tau_d at once (less what the low-pass took in its first dt / tau_d),
  // then settles on the request.
  CHECK(equalised(eq, request(5.0f, 0.1f), kDt_s).torque_Nm[0] == Approx(0.2f - 0.1f / 30.0f).margin(1e-5f));
  MixerInput y{};
  for (int k = 0; k < 500; ++k) y = equalised(eq, request(5.0f, 0.1f), kDt_s);
  CHECK(y.torque_Nm[0] == Approx(0.1f).margin(1e-4f));
  CHECK(y.thrust_N == Approx(5.0f).margin(1e-4f));
}

TEST_CASE("a lag that is no propeller motor's is refused and the last one kept") {
  MotorLagEqualiser eq(kDesign_s);
  REQUIRE(eq.set_motor_time_constant(0.05f));
  CHECK_FALSE(eq.set_motor_time_constant(0.005f));
  CHECK_FALSE(eq.set_motor_time_constant(0.2f));
  CHECK_FALSE(eq.set_motor_time_constant(std::numeric_limits<float>::quiet_NaN()));
  CHECK_FALSE(eq.set_motor_time_constant(std::numeric_limits<float>::infinity()));
  CHECK(eq.motor_time_constant_s() == 0.05f);
  MotorLagEqualiser no_design(0.0f);
  CHECK_FALSE(no_design.set_motor_time_constant(0.05f));
}

TEST_CASE("a non-finite request or dt disturbs nothing; the filter starts at rest") {
  MotorLagEqualiser eq(kDesign_s);
  REQUIRE(eq.set_motor_time_constant(0.06f));
  // Started on its first request: no lead kick when the motors start.
  CHECK(equalised(eq, request(5.0f), kDt_s).thrust_N == 5.0f);
  const MixerInput bad = request(std::numeric_limits<float>::quiet_NaN());
  CHECK(std::isnan(equalised(eq, bad, kDt_s).thrust_N));
  CHECK(equalised(eq, request(5.0f), std::numeric_limits<float>::quiet_NaN()).thrust_N == Approx(5.0f));
  CHECK(equalised(eq, request(5.0f), -1.0f).thrust_N == Approx(5.0f));
  eq.reset();
  CHECK(equalised(eq, request(9.0f), kDt_s).thrust_N == 9.0f);
}
