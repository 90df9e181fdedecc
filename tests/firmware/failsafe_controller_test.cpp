// The on-board law of a hold and a failsafe: levelling, the vertical-speed loop, ground contact.
#include <catch2/catch.hpp>

#include <cmath>

#include "fw/failsafe_controller.hpp"
#include "pa/constants.hpp"

namespace {

using fw::FailsafeController;
using fw::Vec3f;

constexpr float kG = pa::kGravityFloat_mps2;
constexpr float kDt_s = 0.001f;
const Vec3f kLevel{0.0f, 0.0f, 1.0f};

fw::SupervisorConfig config() { return fw::SupervisorConfig{}; }

}  // namespace

TEST_CASE("the levelling law turns the measured up towards the body z-axis") {
  const fw::SupervisorConfig c = config();
  const FailsafeController f(c);
  const float k = c.level_gain_per_s;
  // Up leans towards body +x (the vehicle pitched nose-down about y): pitch back, at k per radian.
  const Vec3f up{std::sin(0.1f), 0.0f, std::cos(0.1f)};
  const Vec3f w = f.levelling_rates(up);
  CHECK(w[0] == 0.0f);
  CHECK(w[1] == k * up[0]);
  CHECK(w[2] == 0.0f);
  // u' = -w x u: the x component of up shrinks.
  CHECK(-(w[1] * up[2] - w[2] * up[1]) < 0.0f);
  const Vec3f w2 = f.levelling_rates(Vec3f{0.0f, 0.2f, 0.98f});
  CHECK(w2[0] == -k * 0.2f);
  CHECK(w2[1] == 0.0f);
  CHECK(f.levelling_rates(kLevel) == Vec3f{-0.0f, 0.0f, 0.0f});
}

TEST_CASE("the levelled hover holds zero vertical speed, compensating tilt up to 60 degrees") {
  FailsafeController f(config());
  CHECK(f.hover_thrust_mps2(kLevel) == kG);
  f.start(-0.5f);  // sinking when the failsafe began
  CHECK(f.vz_mps() == -0.5f);
  CHECK(f.hover_thrust_mps2(kLevel) == Approx(kG + FailsafeController::kVerticalGain_per_s * 0.5f));
  f.start(0.0f);
  CHECK(f.hover_thrust_mps2(Vec3f{0.6f, 0.0f, 0.8f}) == Approx(kG / 0.8f));
  // Beyond 60 degrees the compensation stops at 1 / kMinTiltCos.
  CHECK(f.hover_thrust_mps2(Vec3f{0.95f, 0.0f, 0.3f}) == Approx(kG / FailsafeController::kMinTiltCos));
}

TEST_CASE("the vertical speed integrates the specific force less g, with the step clamped") {
  FailsafeController f(config());
  for (int i = 0; i < 100; ++i) f.integrate(kG + 1.0f, kDt_s);
  CHECK(f.vz_mps() == Approx(0.1f).epsilon(1e-4));
  f.start(0.0f);
  f.integrate(kG - 2.0f, 0.05f);  // a late sample counts as kDtMax_s
  CHECK(f.vz_mps() == Approx(-2.0f * FailsafeController::kDtMax_s));
  f.integrate(kG + 5.0f, -0.001f);  // a clock step back integrates nothing
  CHECK(f.vz_mps() == Approx(-2.0f * FailsafeController::kDtMax_s));
  f.on_touchdown();
  CHECK(f.vz_mps() == 0.0f);
}

TEST_CASE("the descent settles at descent_rate_mps with the loop's time constant") {
  const fw::SupervisorConfig c = config();
  FailsafeController f(c);
  const float k = FailsafeController::kVerticalGain_per_s;
  CHECK(f.descend(kLevel, kG, kG, kDt_s) == Approx(kG - k * c.descent_rate_mps));
  // A point mass flown by the law: its speed follows -rate (1 - exp(-k t)).
  float thrust = 0.0f;
  for (int i = 0; i < 1000; ++i) {
    thrust = f.descend(kLevel, thrust, thrust, kDt_s);
    f.integrate(thrust, kDt_s);
    if (i == 249)
      CHECK(f.vz_mps() == Approx(-c.descent_rate_mps * (1.0f - std::exp(-k * 0.25f))).epsilon(0.01));
  }
  CHECK(f.vz_mps() == Approx(-c.descent_rate_mps).epsilon(0.03));
  CHECK_FALSE(f.on_ground());
  // Climbing fast, the law would ask for negative thrust: none.
  f.start(3.0f);
  CHECK(f.descend(kLevel, kG, kG, kDt_s) == 0.0f);
}

TEST_CASE("ground contact is the floor's support sustained for ground_contact_us") {
  const fw::SupervisorConfig c = config();
  FailsafeController f(c);
  const float held = kG - c.ground_contact_mps2 - 0.5f;  // the thrust applied, less than read
  const int ticks = static_cast<int>(c.ground_contact_us / 1000u);
  for (int i = 0; i < ticks - 1; ++i) f.descend(kLevel, kG, held, kDt_s);
  CHECK_FALSE(f.on_ground());
  f.descend(kLevel, kG, kG, kDt_s);  // no support for one tick: it starts again
  for (int i = 0; i < ticks - 1; ++i) f.descend(kLevel, kG, held, kDt_s);
  CHECK_FALSE(f.on_ground());
  f.descend(kLevel, kG, held, kDt_s);
  f.descend(kLevel, kG, held, kDt_s);
  CHECK(f.on_ground());
  f.clear_ground_contact();
  CHECK_FALSE(f.on_ground());
  for (int i = 0; i < ticks + 1; ++i) f.descend(kLevel, kG, held, kDt_s);
  CHECK(f.on_ground());
  f.start(0.0f);
  CHECK_FALSE(f.on_ground());
}
