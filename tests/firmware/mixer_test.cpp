// The X-quadrocopter mixer: conventions, exact allocation, and every saturation corner of the
// priority roll/pitch > collective > yaw.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <random>

#include "fw/mixer.hpp"

namespace {

using fw::Mixer;
using fw::MixerInput;
using fw::MixerOutput;
using fw::Motors;
using fw::Vec3f;
namespace sat = fw::saturation;

constexpr float kTolThrust_N = 1e-4f;
constexpr float kTolTorque_Nm = 1e-5f;

const fw::AirframeConfig kAirframe{};

// The motors' geometry written out independently of the mixer's sign tables: position in the
// body frame (x forward, y left) and spin seen from above (+1 counter-clockwise).
struct Rotor {
  float x_m, y_m;
  int ccw;
};
std::array<Rotor, 4> rotors() {
  const float a = kAirframe.arm_length_m / std::sqrt(2.0f);
  return {{{a, -a, 1}, {-a, a, 1}, {a, a, -1}, {-a, -a, -1}}};
}

// Thrust and torque of the given motor thrusts: r x (0, 0, f) plus the drag reaction, which
// opposes each rotor's spin.
MixerInput wrench(const Motors& f) {
  MixerInput w;
  const auto r = rotors();
  for (int i = 0; i < 4; ++i) {
    w.thrust_N += f[i];
    w.torque_Nm[0] += r[i].y_m * f[i];
    w.torque_Nm[1] += -r[i].x_m * f[i];
    w.torque_Nm[2] += -static_cast<float>(r[i].ccw) * kAirframe.yaw_moment_per_thrust_m * f[i];
  }
  return w;
}

float hover_N() { return kAirframe.mass_kg * 9.81f; }
float lo_N() { return kAirframe.motor_thrust_min_N; }
float hi_N() { return kAirframe.motor_thrust_max_N; }

bool at_lo(float f) { return std::fabs(f - lo_N()) < 1e-5f; }
bool at_hi(float f) { return std::fabs(f - hi_N()) < 1e-5f; }

void require_motors_in_bounds(const MixerOutput& out) {
  for (int i = 0; i < 4; ++i) {
    REQUIRE(out.thrust_N[i] >= lo_N());
    REQUIRE(out.thrust_N[i] <= hi_N());
    REQUIRE(out.command[i] == Approx(out.thrust_N[i] / hi_N()).margin(1e-7));
    REQUIRE(out.command[i] >= lo_N() / hi_N() - 1e-7f);
    REQUIRE(out.command[i] <= 1.0f);
  }
}

// unallocated == requested - achieved, with "achieved" from the independent geometry.
void require_unallocated_consistent(const MixerInput& in, const MixerOutput& out) {
  const MixerInput got = wrench(out.thrust_N);
  REQUIRE(out.thrust_unallocated_N == Approx(in.thrust_N - got.thrust_N).margin(kTolThrust_N));
  for (int a = 0; a < 3; ++a) {
    REQUIRE(out.torque_unallocated_Nm[a] == Approx(in.torque_Nm[a] - got.torque_Nm[a]).margin(kTolTorque_Nm));
  }
}

MixerOutput mix(float thrust_N, Vec3f torque_Nm) {
  const Mixer mixer(kAirframe);
  const MixerInput in{thrust_N, torque_Nm};
  const MixerOutput out = mixer.mix(in);
  require_motors_in_bounds(out);
  require_unallocated_consistent(in, out);
  return out;
}

}  // namespace

TEST_CASE("mixer: nominal request is reconstructed exactly with no flags") {
  const MixerInput in{hover_N(), {0.05f, -0.03f, 0.01f}};
  const MixerOutput out = mix(in.thrust_N, in.torque_Nm);
  CHECK(int(out.saturation) == 0);
  const MixerInput got = wrench(out.thrust_N);
  CHECK(got.thrust_N == Approx(in.thrust_N).margin(kTolThrust_N));
  for (int a = 0; a < 3; ++a) {
    CHECK(got.torque_Nm[a] == Approx(in.torque_Nm[a]).margin(kTolTorque_Nm));
    CHECK(std::fabs(out.torque_unallocated_Nm[a]) < kTolTorque_Nm);
  }
  CHECK(std::fabs(out.thrust_unallocated_N) < kTolThrust_N);
}

TEST_CASE("mixer: effect() is the forward model of the documented geometry") {
  const Mixer mixer(kAirframe);
  const Motors f{0.3f, 1.7f, 2.2f, 0.9f};
  const MixerInput e = mixer.effect(f);
  const MixerInput w = wrench(f);
  CHECK(e.thrust_N == Approx(w.thrust_N));
  for (int a = 0; a < 3; ++a) CHECK(e.torque_Nm[a] == Approx(w.torque_Nm[a]).margin(1e-6));
}

TEST_CASE("mixer: sign conventions (x forward, y left, z up, right-hand torques)") {
  const float t = hover_N();
  SECTION("positive roll lifts the left side: left motors 1 and 2 push harder") {
    const MixerOutput out = mix(t, {0.1f, 0.0f, 0.0f});
    CHECK(out.thrust_N[1] > out.thrust_N[0]);
    CHECK(out.thrust_N[2] > out.thrust_N[3]);
  }
  SECTION("positive pitch lowers the nose: rear motors 1 and 3 push harder") {
    const MixerOutput out = mix(t, {0.0f, 0.1f, 0.0f});
    CHECK(out.thrust_N[1] > out.thrust_N[2]);
    CHECK(out.thrust_N[3] > out.thrust_N[0]);
  }
  SECTION("positive yaw: clockwise rotors 2 and 3 push harder (their drag turns the body left)") {
    const MixerOutput out = mix(t, {0.0f, 0.0f, 0.02f});
    CHECK(out.thrust_N[2] > out.thrust_N[0]);
    CHECK(out.thrust_N[3] > out.thrust_N[1]);
  }
}

TEST_CASE("mixer: collective high keeps the torques and flags only collective_high") {
  SECTION("no torque: every motor at maximum") {
    const MixerOutput out = mix(20.0f, {0.0f, 0.0f, 0.0f});
    CHECK(int(out.saturation) == sat::collective_high);
    for (float f : out.thrust_N) CHECK(at_hi(f));
    CHECK(out.thrust_unallocated_N == Approx(20.0f - 4.0f * hi_N()).margin(kTolThrust_N));
  }
  SECTION("with roll and pitch: torques exact, the busiest motor at maximum") {
    const Vec3f tau{0.2f, -0.1f, 0.0f};
    const MixerOutput out = mix(20.0f, tau);
    CHECK(int(out.saturation) == sat::collective_high);
    const MixerInput got = wrench(out.thrust_N);
    for (int a = 0; a < 3; ++a) CHECK(got.torque_Nm[a] == Approx(tau[a]).margin(kTolTorque_Nm));
    int n_hi = 0;
    for (float f : out.thrust_N) n_hi += at_hi(f) ? 1 : 0;
    CHECK(n_hi >= 1);
    CHECK(out.thrust_unallocated_N > 0.0f);
  }
}

TEST_CASE("mixer: collective low keeps the torques and flags only collective_low") {
  SECTION("zero thrust request: every motor at idle") {
    const MixerOutput out = mix(0.0f, {0.0f, 0.0f, 0.0f});
    CHECK(int(out.saturation) == sat::collective_low);
    for (float f : out.thrust_N) CHECK(at_lo(f));
    CHECK(out.thrust_unallocated_N == Approx(-4.0f * lo_N()).margin(kTolThrust_N));
  }
  SECTION("negative thrust request with roll: roll exact, thrust raised") {
    const Vec3f tau{-0.3f, 0.0f, 0.0f};
    const MixerOutput out = mix(-3.0f, tau);
    CHECK(int(out.saturation) == sat::collective_low);
    const MixerInput got = wrench(out.thrust_N);
    for (int a = 0; a < 3; ++a) CHECK(got.torque_Nm[a] == Approx(tau[a]).margin(kTolTorque_Nm));
    CHECK(out.thrust_unallocated_N < 0.0f);
  }
}

TEST_CASE("mixer: a single axis beyond the span is cut to the largest torque the motors give") {
  // Full span on the diagonal pairs: |tau| = 2 a (max - min) for roll alone or pitch alone.
  const float a_m = kAirframe.arm_length_m / std::sqrt(2.0f);
  const float full_Nm = 2.0f * a_m * (hi_N() - lo_N());
  // Half of hover thrust with the motors split evenly between min and max requires
  // 4 (min + max) / 2 thrust; request that exactly so the collective is not cut.
  const float mid_thrust_N = 2.0f * (lo_N() + hi_N());
  struct Case {
    int axis;
    float sign;
    std::uint8_t flag;
  };
  const Case cases[] = {{0, 1.0f, sat::roll_pos},
                        {0, -1.0f, sat::roll_neg},
                        {1, 1.0f, sat::pitch_pos},
                        {1, -1.0f, sat::pitch_neg}};
  for (const Case& c : cases) {
    Vec3f tau{0.0f, 0.0f, 0.0f};
    tau[c.axis] = c.sign * 3.0f * full_Nm;
    const MixerOutput out = mix(mid_thrust_N, tau);
    INFO("axis " << c.axis << " sign " << c.sign);
    CHECK((out.saturation & ~(sat::collective_high | sat::collective_low)) == int(c.flag));
    const MixerInput got = wrench(out.thrust_N);
    CHECK(got.torque_Nm[c.axis] == Approx(c.sign * full_Nm).margin(1e-4));
    CHECK(got.torque_Nm[1 - c.axis] == Approx(0.0f).margin(kTolTorque_Nm));
    CHECK(got.thrust_N == Approx(mid_thrust_N).margin(1e-3));
    CHECK(out.torque_unallocated_Nm[c.axis] * c.sign > 0.0f);
    // Two motors at idle, two at maximum: the whole span is used for the axis.
    int n_lo = 0, n_hi = 0;
    for (float f : out.thrust_N) {
      n_lo += at_lo(f) ? 1 : 0;
      n_hi += at_hi(f) ? 1 : 0;
    }
    CHECK(n_lo == 2);
    CHECK(n_hi == 2);
  }
}

TEST_CASE("mixer: roll before collective at hover thrust") {
  // At hover thrust the split min/max motors need more collective than requested: the roll
  // torque is kept and the collective is raised (flagged low).
  const MixerOutput out = mix(hover_N(), {5.0f, 0.0f, 0.0f});
  CHECK(int(out.saturation) == (sat::roll_pos | sat::collective_low));
  CHECK(out.thrust_unallocated_N < 0.0f);
}

TEST_CASE("mixer: roll and pitch together beyond the span keep their direction") {
  const Vec3f tau{1.0f, -0.6f, 0.0f};
  const MixerOutput out = mix(2.0f * (lo_N() + hi_N()), tau);
  CHECK((out.saturation & (sat::roll_pos | sat::roll_neg | sat::pitch_pos | sat::pitch_neg)) ==
        int(sat::roll_pos | sat::pitch_neg));
  const MixerInput got = wrench(out.thrust_N);
  CHECK(got.torque_Nm[0] > 0.0f);
  CHECK(got.torque_Nm[1] < 0.0f);
  CHECK(got.torque_Nm[0] / got.torque_Nm[1] == Approx(tau[0] / tau[1]).epsilon(1e-4));
  // Scaled to exactly fill the span: |roll| + |pitch| = 2 a (max - min).
  const float a_m = kAirframe.arm_length_m / std::sqrt(2.0f);
  CHECK(std::fabs(got.torque_Nm[0]) + std::fabs(got.torque_Nm[1]) ==
        Approx(2.0f * a_m * (hi_N() - lo_N())).epsilon(1e-4));
}

TEST_CASE("mixer: yaw saturates last and keeps roll, pitch and collective") {
  for (float sign : {1.0f, -1.0f}) {
    INFO("yaw sign " << sign);
    const Vec3f tau{0.1f, 0.05f, sign * 0.5f};
    const MixerOutput out = mix(hover_N(), tau);
    CHECK(int(out.saturation) == (sign > 0.0f ? sat::yaw_pos : sat::yaw_neg));
    const MixerInput got = wrench(out.thrust_N);
    CHECK(got.thrust_N == Approx(hover_N()).margin(kTolThrust_N));
    CHECK(got.torque_Nm[0] == Approx(tau[0]).margin(kTolTorque_Nm));
    CHECK(got.torque_Nm[1] == Approx(tau[1]).margin(kTolTorque_Nm));
    CHECK(got.torque_Nm[2] * sign > 0.0f);
    CHECK(std::fabs(got.torque_Nm[2]) < std::fabs(tau[2]));
    CHECK(out.torque_unallocated_Nm[2] * sign > 0.0f);
    // The largest yaw that fits: a motor that yaw pushes in the requested direction is at
    // its bound, so no more yaw is possible.
    bool blocked = false;
    for (int i = 0; i < 4; ++i) {
      const float push = Mixer::kYawSign[i] * sign;
      blocked = blocked || (push > 0.0f && at_hi(out.thrust_N[i])) || (push < 0.0f && at_lo(out.thrust_N[i]));
    }
    CHECK(blocked);
  }
}

TEST_CASE("mixer: combined corners") {
  SECTION("high collective leaves little yaw authority; collective itself is met") {
    const MixerOutput out = mix(12.0f, {0.0f, 0.0f, 0.2f});
    CHECK(int(out.saturation) == sat::yaw_pos);
    CHECK(wrench(out.thrust_N).thrust_N == Approx(12.0f).margin(kTolThrust_N));
  }
  SECTION("roll saturated, collective high, yaw gets nothing") {
    const MixerOutput out = mix(20.0f, {-2.0f, 0.0f, 0.1f});
    CHECK(int(out.saturation) == (sat::roll_neg | sat::collective_high | sat::yaw_pos));
    CHECK(wrench(out.thrust_N).torque_Nm[2] == Approx(0.0f).margin(kTolTorque_Nm));
    CHECK(out.torque_unallocated_Nm[2] == Approx(0.1f).margin(kTolTorque_Nm));
  }
  SECTION("pitch saturated, collective low, negative yaw") {
    const MixerOutput out = mix(0.0f, {0.0f, 3.0f, -0.1f});
    CHECK(int(out.saturation) == (sat::pitch_pos | sat::collective_low | sat::yaw_neg));
  }
  SECTION("low collective with moderate torques: only the collective is raised") {
    // Motor 0 sits at idle after the collective is raised just enough for roll and pitch;
    // negative yaw lifts it, so all of this yaw fits.
    const Vec3f tau{0.02f, 0.02f, -0.005f};
    const MixerOutput out = mix(0.1f, tau);
    CHECK(int(out.saturation) == sat::collective_low);
    const MixerInput got = wrench(out.thrust_N);
    for (int a = 0; a < 3; ++a) CHECK(got.torque_Nm[a] == Approx(tau[a]).margin(kTolTorque_Nm));
  }
  SECTION("collective is not raised further to make room for yaw") {
    // The same request with positive yaw would push idle motor 0 lower: yaw is cut, the
    // collective stays at the lowest value roll and pitch need.
    const Vec3f tau{0.02f, 0.02f, 0.005f};
    const MixerOutput low = mix(0.1f, tau);
    const MixerOutput ref = mix(0.1f, {0.02f, 0.02f, 0.0f});
    CHECK(int(low.saturation) == (sat::collective_low | sat::yaw_pos));
    CHECK(wrench(low.thrust_N).thrust_N == Approx(wrench(ref.thrust_N).thrust_N).margin(kTolThrust_N));
    CHECK(at_lo(low.thrust_N[0]));
  }
}

TEST_CASE("mixer: non-finite requests put every motor at idle and set every flag") {
  const Mixer mixer(kAirframe);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  const MixerInput bad[] = {{nan, {0.0f, 0.0f, 0.0f}},
                            {hover_N(), {inf, 0.0f, 0.0f}},
                            {hover_N(), {0.0f, -inf, 0.0f}},
                            {hover_N(), {0.0f, 0.0f, nan}},
                            {inf, {0.0f, 0.0f, 0.0f}}};
  for (const MixerInput& in : bad) {
    const MixerOutput out = mixer.mix(in);
    CHECK(int(out.saturation) == 0xFF);
    for (int i = 0; i < 4; ++i) {
      CHECK(out.thrust_N[i] == lo_N());
      CHECK(out.command[i] == Approx(lo_N() / hi_N()));
    }
    CHECK(out.thrust_unallocated_N == 0.0f);
    for (float t : out.torque_unallocated_Nm) CHECK(t == 0.0f);
  }
}

TEST_CASE("mixer: an unusable configuration is refused with motors at zero") {
  fw::AirframeConfig bad = kAirframe;
  SECTION("max not above min") { bad.motor_thrust_max_N = bad.motor_thrust_min_N; }
  SECTION("zero arm") { bad.arm_length_m = 0.0f; }
  SECTION("negative yaw moment") { bad.yaw_moment_per_thrust_m = -0.01f; }
  SECTION("non-finite max") { bad.motor_thrust_max_N = std::numeric_limits<float>::infinity(); }
  const Mixer mixer(bad);
  CHECK_FALSE(mixer.valid());
  const MixerOutput out = mixer.mix({hover_N(), {0.0f, 0.0f, 0.0f}});
  CHECK(int(out.saturation) == 0xFF);
  for (int i = 0; i < 4; ++i) {
    CHECK(out.thrust_N[i] == 0.0f);
    CHECK(out.command[i] == 0.0f);
  }
  CHECK(Mixer(kAirframe).valid());
}

TEST_CASE("mixer: randomised sweep keeps motors in bounds and the report consistent") {
  const Mixer mixer(kAirframe);
  std::mt19937 rng(20130903u);
  std::uniform_real_distribution<float> thrust(-5.0f, 20.0f);
  std::uniform_real_distribution<float> tilt(-1.5f, 1.5f);
  std::uniform_real_distribution<float> yaw(-0.3f, 0.3f);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  int n_flagged = 0, n_clean = 0;
  for (int n = 0; n < 20000; ++n) {
    // Mix of small requests (often feasible) and large ones (often saturated).
    const float shrink = unit(rng) < 0.5f ? 0.05f : 1.0f;
    const MixerInput in{thrust(rng), {shrink * tilt(rng), shrink * tilt(rng), shrink * yaw(rng)}};
    const MixerOutput out = mixer.mix(in);
    INFO("n=" << n << " T=" << in.thrust_N << " tau=" << in.torque_Nm[0] << "," << in.torque_Nm[1] << ","
              << in.torque_Nm[2] << " flags=" << int(out.saturation));
    require_motors_in_bounds(out);
    require_unallocated_consistent(in, out);
    (out.saturation == 0 ? n_clean : n_flagged) += 1;

    // An axis with no flag in either direction is delivered exactly.
    for (int a = 0; a < 3; ++a) {
      if ((out.saturation & (fw::saturation::positive(a) | fw::saturation::negative(a))) == 0) {
        REQUIRE(std::fabs(out.torque_unallocated_Nm[a]) < kTolTorque_Nm);
      }
    }
    if ((out.saturation & (sat::collective_high | sat::collective_low)) == 0) {
      REQUIRE(std::fabs(out.thrust_unallocated_N) < kTolThrust_N);
    }
    // Flags point the way the shortfall does.
    if (out.saturation & sat::collective_high) REQUIRE(out.thrust_unallocated_N > 0.0f);
    if (out.saturation & sat::collective_low) REQUIRE(out.thrust_unallocated_N < 0.0f);
    if (out.saturation & sat::roll_pos) REQUIRE(out.torque_unallocated_Nm[0] > 0.0f);
    if (out.saturation & sat::roll_neg) REQUIRE(out.torque_unallocated_Nm[0] < 0.0f);
    if (out.saturation & sat::pitch_pos) REQUIRE(out.torque_unallocated_Nm[1] > 0.0f);
    if (out.saturation & sat::pitch_neg) REQUIRE(out.torque_unallocated_Nm[1] < 0.0f);
    if (out.saturation & sat::yaw_pos) REQUIRE(out.torque_unallocated_Nm[2] > -kTolTorque_Nm);
    if (out.saturation & sat::yaw_neg) REQUIRE(out.torque_unallocated_Nm[2] < kTolTorque_Nm);
    // Priority: when roll or pitch is cut, the motors use the whole span.
    if (out.saturation & (sat::roll_pos | sat::roll_neg | sat::pitch_pos | sat::pitch_neg)) {
      bool any_lo = false, any_hi = false;
      for (float f : out.thrust_N) {
        any_lo = any_lo || at_lo(f);
        any_hi = any_hi || at_hi(f);
      }
      REQUIRE(any_lo);
      REQUIRE(any_hi);
    }
  }
  // The sweep exercised both regimes.
  CHECK(n_clean > 1000);
  CHECK(n_flagged > 1000);
}

TEST_CASE("mixer: extreme finite requests stay in bounds and are reported") {
  const Mixer mixer(kAirframe);
  const float big = std::numeric_limits<float>::max();
  const MixerInput in{big, {-big, big, -big}};
  const MixerOutput out = mixer.mix(in);
  require_motors_in_bounds(out);
  CHECK(int(out.saturation) == (sat::roll_neg | sat::pitch_pos | sat::collective_high | sat::yaw_neg));
  CHECK(std::isfinite(out.thrust_unallocated_N));
  for (float t : out.torque_unallocated_Nm) CHECK(std::isfinite(t));
  CHECK(out.torque_unallocated_Nm[0] < 0.0f);
  CHECK(out.torque_unallocated_Nm[1] > 0.0f);
}
