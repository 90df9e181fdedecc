// The body-rate PI loop: response, closed-loop disturbance rejection, input validation and
// per-direction anti-windup.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "fw/rate_controller.hpp"

namespace {

using fw::RateController;
using fw::Vec3f;
namespace sat = fw::saturation;

const fw::RateControllerConfig kRate{};
const fw::AirframeConfig kAirframe{};
constexpr float kDt_s = 0.001f;

float inertia(int axis) { return kAirframe.inertia_kgm2[axis]; }

}  // namespace

TEST_CASE("rate controller: proportional response has the right sign and size") {
  RateController rc(kRate, kAirframe);
  const Vec3f setpoint{1.0f, -0.5f, 0.25f};
  const Vec3f gyro{0.2f, 0.0f, 0.5f};
  const Vec3f tau = rc.update(setpoint, gyro, kDt_s, 0);
  for (int a = 0; a < 3; ++a) {
    const float e = setpoint[a] - gyro[a];
    CHECK(tau[a] == Approx(inertia(a) * kRate.kp_per_s[a] * e).epsilon(1e-6));
  }
  CHECK(tau[0] > 0.0f);
  CHECK(tau[1] < 0.0f);
  CHECK(tau[2] < 0.0f);  // spinning faster than commanded about z: brake
}

TEST_CASE("rate controller: the integrator accumulates ki e dt and feeds the next output") {
  RateController rc(kRate, kAirframe);
  const Vec3f setpoint{1.0f, 0.0f, -2.0f};
  const Vec3f gyro{};
  rc.update(setpoint, gyro, kDt_s, 0);
  for (int a = 0; a < 3; ++a) {
    CHECK(rc.integrator()[a] == Approx(kRate.ki_per_s2[a] * setpoint[a] * kDt_s).margin(1e-7));
  }
  const Vec3f tau = rc.update(setpoint, gyro, kDt_s, 0);
  for (int a = 0; a < 3; ++a) {
    const float expected =
        inertia(a) * (kRate.kp_per_s[a] * setpoint[a] + kRate.ki_per_s2[a] * setpoint[a] * kDt_s);
    CHECK(tau[a] == Approx(expected).epsilon(1e-6));
  }
}

namespace {

// Closed loop on a rigid body, J w_dot = torque + disturbance, 1 kHz, explicit Euler.
// Returns the final rate error per axis.
Vec3f run_closed_loop(const fw::RateControllerConfig& config, const Vec3f& setpoint,
                      const Vec3f& disturbance_Nm, float duration_s, Vec3f* integrator_out) {
  RateController rc(config, kAirframe);
  Vec3f w{};
  const int steps = static_cast<int>(duration_s / kDt_s);
  for (int k = 0; k < steps; ++k) {
    const Vec3f tau = rc.update(setpoint, w, kDt_s, 0);
    for (int a = 0; a < 3; ++a) w[a] += (tau[a] + disturbance_Nm[a]) / inertia(a) * kDt_s;
  }
  if (integrator_out != nullptr) *integrator_out = rc.integrator();
  return {setpoint[0] - w[0], setpoint[1] - w[1], setpoint[2] - w[2]};
}

}  // namespace

TEST_CASE("rate controller: the integrator removes a constant disturbance in closed loop") {
  const Vec3f setpoint{0.5f, -0.3f, 0.2f};
  const Vec3f disturbance{0.02f, -0.015f, 0.008f};  // e.g. an off-centre pole and a yaw drag bias

  Vec3f integrator{};
  const Vec3f err = run_closed_loop(kRate, setpoint, disturbance, 8.0f, &integrator);
  for (int a = 0; a < 3; ++a) {
    INFO("axis " << a);
    CHECK(std::fabs(err[a]) < 1e-3f);
    // At rest the integral term cancels the disturbance's angular acceleration.
    CHECK(integrator[a] == Approx(-disturbance[a] / inertia(a)).epsilon(1e-2));
  }

  // Without the integral the same loop keeps the proportional droop d / (J kp).
  fw::RateControllerConfig p_only = kRate;
  for (float& ki : p_only.ki_per_s2) ki = 0.0f;
  const Vec3f droop = run_closed_loop(p_only, setpoint, disturbance, 8.0f, nullptr);
  for (int a = 0; a < 3; ++a) {
    INFO("axis " << a);
    CHECK(droop[a] == Approx(-disturbance[a] / (inertia(a) * kRate.kp_per_s[a])).epsilon(1e-2));
    CHECK(std::fabs(droop[a]) > 0.1f);
  }
}

TEST_CASE("rate controller: dt is clamped into [dt_min_s, dt_max_s]") {
  const Vec3f setpoint{1.0f, 1.0f, 1.0f};
  const Vec3f gyro{};
  const auto step_with = [&](float dt_s) {
    RateController rc(kRate, kAirframe);
    rc.update(setpoint, gyro, dt_s, 0);
    return rc.integrator()[0] / kRate.ki_per_s2[0];  // the dt actually used
  };
  CHECK(step_with(0.0f) == Approx(kRate.dt_min_s));
  CHECK(step_with(-0.5f) == Approx(kRate.dt_min_s));
  CHECK(step_with(1e-7f) == Approx(kRate.dt_min_s));
  CHECK(step_with(0.002f) == Approx(0.002f));
  CHECK(step_with(1.0f) == Approx(kRate.dt_max_s));
  CHECK(step_with(1e30f) == Approx(kRate.dt_max_s));
}

TEST_CASE("rate controller: non-finite input holds the last output and the integrators") {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  RateController rc(kRate, kAirframe);
  const Vec3f setpoint{1.0f, -1.0f, 0.5f};
  rc.update(setpoint, {}, kDt_s, 0);
  const Vec3f held = rc.update(setpoint, {}, kDt_s, 0);
  const Vec3f integrator = rc.integrator();

  struct Bad {
    Vec3f setpoint, gyro;
    float dt_s;
  };
  const Bad bad[] = {{{nan, 0.0f, 0.0f}, {}, kDt_s},
                     {setpoint, {0.0f, inf, 0.0f}, kDt_s},
                     {setpoint, {0.0f, 0.0f, -inf}, kDt_s},
                     {setpoint, {}, nan},
                     {setpoint, {}, inf},
                     // finite but so large that the torque overflows
                     {setpoint, {3e38f, 0.0f, 0.0f}, kDt_s}};
  for (const Bad& b : bad) {
    const Vec3f tau = rc.update(b.setpoint, b.gyro, b.dt_s, 0);
    for (int a = 0; a < 3; ++a) {
      CHECK(tau[a] == held[a]);
      CHECK(rc.integrator()[a] == integrator[a]);
    }
  }
  // A valid sample afterwards continues from the held integrators.
  const Vec3f tau = rc.update(setpoint, {}, kDt_s, 0);
  for (int a = 0; a < 3; ++a) CHECK(std::isfinite(tau[a]));
  CHECK(rc.integrator()[0] > integrator[0]);
}

TEST_CASE("rate controller: anti-windup freezes each axis only in its saturated direction") {
  for (int axis = 0; axis < 3; ++axis) {
    INFO("axis " << axis);
    const int other = (axis + 1) % 3;
    RateController rc(kRate, kAirframe);
    Vec3f up{};
    up[axis] = 1.0f;
    up[other] = 1.0f;
    Vec3f down{};
    down[axis] = -1.0f;
    down[other] = 1.0f;
    // Some integral to start from.
    for (int k = 0; k < 10; ++k) rc.update(up, {}, kDt_s, 0);
    const Vec3f start = rc.integrator();

    // Saturated positive: growth blocked on this axis, other axes keep integrating.
    rc.update(up, {}, kDt_s, sat::positive(axis));
    CHECK(rc.integrator()[axis] == start[axis]);
    CHECK(rc.integrator()[other] > start[other]);
    // ... but it may decrease.
    rc.update(down, {}, kDt_s, sat::positive(axis));
    CHECK(rc.integrator()[axis] < start[axis]);

    // Saturated negative: decrease blocked, increase allowed.
    const float before_neg = rc.integrator()[axis];
    rc.update(down, {}, kDt_s, sat::negative(axis));
    CHECK(rc.integrator()[axis] == before_neg);
    rc.update(up, {}, kDt_s, sat::negative(axis));
    CHECK(rc.integrator()[axis] > before_neg);

    // The collective flags do not concern the rate loop.
    const float before_coll = rc.integrator()[axis];
    rc.update(up, {}, kDt_s, sat::collective_high | sat::collective_low);
    CHECK(rc.integrator()[axis] > before_coll);
  }
}

TEST_CASE("rate controller: the integrator is bounded") {
  RateController rc(kRate, kAirframe);
  for (int k = 0; k < 20000; ++k) rc.update({5.0f, -5.0f, 5.0f}, {}, kDt_s, 0);
  CHECK(rc.integrator()[0] == Approx(kRate.integrator_limit_radps2[0]));
  CHECK(rc.integrator()[1] == Approx(-kRate.integrator_limit_radps2[1]));
  CHECK(rc.integrator()[2] == Approx(kRate.integrator_limit_radps2[2]));
}

TEST_CASE("rate controller: setpoints are clamped to the rate limit") {
  const float limit = kRate.rate_limit_radps;
  RateController a(kRate, kAirframe), b(kRate, kAirframe);
  const Vec3f tau_over = a.update({100.0f, -100.0f, 3.0f * limit}, {}, kDt_s, 0);
  const Vec3f tau_at = b.update({limit, -limit, limit}, {}, kDt_s, 0);
  for (int ax = 0; ax < 3; ++ax) {
    CHECK(tau_over[ax] == Approx(tau_at[ax]));
    CHECK(a.integrator()[ax] == Approx(b.integrator()[ax]));
  }
  // The gyro is not clamped: a vehicle spinning beyond the limit is braked in full.
  RateController c(kRate, kAirframe);
  const Vec3f tau_fast = c.update({}, {2.0f * limit, 0.0f, 0.0f}, kDt_s, 0);
  CHECK(tau_fast[0] == Approx(-inertia(0) * kRate.kp_per_s[0] * 2.0f * limit));
}

TEST_CASE("rate controller: reset clears the integrators and the held output") {
  RateController rc(kRate, kAirframe);
  for (int k = 0; k < 100; ++k) rc.update({1.0f, 1.0f, 1.0f}, {}, kDt_s, 0);
  REQUIRE(rc.integrator()[0] != 0.0f);
  rc.reset();
  for (int a = 0; a < 3; ++a) CHECK(rc.integrator()[a] == 0.0f);
  const Vec3f held = rc.update({std::numeric_limits<float>::quiet_NaN(), 0.0f, 0.0f}, {}, kDt_s, 0);
  for (int a = 0; a < 3; ++a) CHECK(held[a] == 0.0f);
  // After reset the first output is purely proportional again.
  const Vec3f tau = rc.update({1.0f, 0.0f, 0.0f}, {}, kDt_s, 0);
  CHECK(tau[0] == Approx(inertia(0) * kRate.kp_per_s[0]));
}

TEST_CASE("rate controller: the identified inertia scales roll and pitch, never yaw, within range") {
  RateController rc(kRate, kAirframe);
  CHECK(rc.inertia_scale() == 1.0f);
  REQUIRE(rc.set_inertia_scale(0.8f));
  const Vec3f setpoint{1.0f, -1.0f, 1.0f};
  const Vec3f tau = rc.update(setpoint, Vec3f{}, kDt_s, 0);
  CHECK(tau[0] == Approx(0.8f * inertia(0) * kRate.kp_per_s[0]).epsilon(1e-6));
  CHECK(tau[1] == Approx(-0.8f * inertia(1) * kRate.kp_per_s[1]).epsilon(1e-6));
  CHECK(tau[2] == Approx(inertia(2) * kRate.kp_per_s[2]).epsilon(1e-6));
  // Out of range or not a number: refused, the scale kept.
  for (float bad :
       {0.4f, 2.5f, -1.0f, std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()})
    CHECK_FALSE(rc.set_inertia_scale(bad));
  CHECK(rc.inertia_scale() == 0.8f);
  // Back to the file's: the law is the airframe's again, bit for bit.
  REQUIRE(rc.set_inertia_scale(1.0f));
  RateController fresh(kRate, kAirframe);
  rc.reset();
  const Vec3f a = rc.update(setpoint, Vec3f{}, kDt_s, 0);
  const Vec3f b = fresh.update(setpoint, Vec3f{}, kDt_s, 0);
  for (int i = 0; i < 3; ++i) CHECK(a[i] == b[i]);
}
