// The motors' lag identified from rate doublets: recovered within 10 % over the range a propeller
// motor spans, with the inertia off by 20 %, a radio's latency and jitter and gyro noise; the
// refusals each for its reason.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "fw/config.hpp"
#include "groundstation/estimation/rate_response.hpp"
#include "groundstation/runtime/ground_station.hpp"

namespace {

using gs::estimation::IdentificationRefusal;
using gs::estimation::RateCommandSample;
using gs::estimation::RateLoopConfig;
using gs::estimation::RateResponseIdentifier;
using gs::estimation::RateTelemetrySample;

struct Vehicle {
  double motor_s = 0.03;
  double inertia_gain = 1.0;  // J_configured / J_true
  double equalised_s = 0.03;  // what the firmware's equaliser is set to
  double disturbance_radps2 = 0.0;
  double inertia_scale = 1.0;  // what the firmware's rate loop takes for J, over the file's
};

struct Recording {
  std::vector<RateCommandSample> commands;
  std::vector<RateTelemetrySample> telemetry;
};

// An independent truth: four motors each lagging on its own (per-motor thrust, mixed into a torque
// by the X geometry), the firmware's PI loop and equaliser at 1 kHz on a noisy gyro, a hover law
// on the ground at 100 Hz holding the attitude, commands and telemetry through a radio 10 ms each
// way with up to 3 ms of jitter.
Recording fly(const Vehicle& v, const RateResponseIdentifier& id, std::uint32_t seed,
              double amplitude_scale = 1.0) {
  const RateLoopConfig loop;
  std::mt19937 rng(seed);
  std::normal_distribution<double> gyro_noise(0.0, 0.005);
  std::uniform_real_distribution<double> jitter(0.0, 0.003);
  const double dt = 0.001, latency = 0.010, tau_d = loop.design_time_constant_s;
  double attitude[2] = {0, 0}, rate[2] = {0, 0}, integral[2] = {0, 0}, eq[2] = {0, 0};
  double motors[4] = {0, 0, 0, 0};
  double setpoint[2] = {0, 0};
  std::vector<std::pair<double, std::array<double, 2>>> uplink;  // due time, rates
  Recording r;
  const double start = 0.5, end = start + id.excitation_duration_s() + 0.3;
  for (int k = 0; k * dt < end; ++k) {
    const double t = k * dt;
    if (k % 10 == 0) {  // the ground's frame: hover law on the attitude plus the excitation
      Eigen::Vector2d cmd(-4.0 * attitude[0], -4.0 * attitude[1]);
      if (t >= start) cmd += amplitude_scale * id.excitation(t - start);
      uplink.push_back({t + latency + jitter(rng), {cmd[0], cmd[1]}});
      if (t >= start) r.commands.push_back({t, cmd});
    }
    for (auto& u : uplink)
      if (u.first <= t && u.first > t - dt) setpoint[0] = u.second[0], setpoint[1] = u.second[1];
    double request[2];
    for (int a = 0; a < 2; ++a) {
      const double gyro = rate[a] + gyro_noise(rng);
      const double e = std::clamp(setpoint[a], -10.0, 10.0) - gyro;
      integral[a] = std::clamp(integral[a] + loop.ki_per_s2[a] * e * dt, -20.0, 20.0);
      const double u = loop.kp_per_s[a] * e + integral[a];
      eq[a] += dt / tau_d * (u - eq[a]);
      request[a] = v.equalised_s / tau_d * u + (1.0 - v.equalised_s / tau_d) * eq[a];
    }
    // Per motor (roll signs -,+,+,-; pitch -,+,-,+), each lagging; the torque mixes back.
    const double roll_sign[4] = {-1, 1, 1, -1}, pitch_sign[4] = {-1, 1, -1, 1};
    double achieved[2] = {0, 0};
    for (int m = 0; m < 4; ++m) {
      const double cmd = 0.25 * (roll_sign[m] * request[0] + pitch_sign[m] * request[1]);
      motors[m] += (cmd - motors[m]) * (1.0 - std::exp(-dt / v.motor_s));
      achieved[0] += roll_sign[m] * motors[m];
      achieved[1] += pitch_sign[m] * motors[m];
    }
    for (int a = 0; a < 2; ++a) {
      rate[a] += (v.inertia_gain * v.inertia_scale * achieved[a] + v.disturbance_radps2) * dt;
      attitude[a] += rate[a] * dt;
    }
    if (k % 5 == 0 && t >= start)
      r.telemetry.push_back({t + latency + jitter(rng),
                             Eigen::Vector2d(rate[0] + gyro_noise(rng), rate[1] + gyro_noise(rng)), false});
  }
  std::sort(r.telemetry.begin(), r.telemetry.end(),
            [](const auto& a, const auto& b) { return a.t_s < b.t_s; });
  return r;
}

}  // namespace

TEST_CASE("the motors' lag is identified within 10 % from 20 to 60 ms, the inertia 20 % off") {
  const RateResponseIdentifier id{RateLoopConfig{}};
  std::uint32_t seed = 1;
  for (const double motor_s : {0.02, 0.03, 0.045, 0.06}) {
    for (const double gain : {0.83, 1.0, 1.25}) {
      const Vehicle v{motor_s, gain, 0.03, 0.3};
      const Recording r = fly(v, id, seed++);
      const auto result = id.fit(r.commands, r.telemetry, v.equalised_s);
      INFO("motor " << motor_s << " s, inertia gain " << gain << ": "
                    << gs::estimation::refusal_name(result.refusal));
      REQUIRE(result.identified);
      INFO("identified " << result.identified->time_constant_s << " s in ["
                         << result.identified->time_constant_low_s << ", "
                         << result.identified->time_constant_high_s << "], gain "
                         << result.identified->inertia_gain << ", round trip "
                         << result.identified->round_trip_s);
      CHECK(result.identified->time_constant_s == Approx(motor_s).epsilon(0.1));
      CHECK(result.identified->time_constant_low_s <= result.identified->time_constant_s);
      CHECK(result.identified->time_constant_high_s >= result.identified->time_constant_s);
      CHECK(result.identified->inertia_gain == Approx(gain).epsilon(0.1));
    }
  }
}

TEST_CASE("identified with the equaliser already set, the motors' own lag comes out") {
  const RateResponseIdentifier id{RateLoopConfig{}};
  const Vehicle v{0.055, 1.0, 0.045, 0.0};
  const Recording r = fly(v, id, 7);
  const auto result = id.fit(r.commands, r.telemetry, v.equalised_s);
  REQUIRE(result.identified);
  CHECK(result.identified->time_constant_s == Approx(0.055).epsilon(0.1));
}

TEST_CASE("identified with the rate loop's inertia already set, the vehicle's own inertia comes out") {
  const RateResponseIdentifier id{RateLoopConfig{}};
  Vehicle v{0.04, 1.25, 0.04, 0.0};
  v.inertia_scale = 0.8;  // J_file / 1.25 on board: the loop is the design's
  const Recording r = fly(v, id, 11);
  const auto result = id.fit(r.commands, r.telemetry, v.equalised_s, v.inertia_scale);
  REQUIRE(result.identified);
  CHECK(result.identified->inertia_gain == Approx(1.25).epsilon(0.1));
  // Fitted as if the file's inertia were on board, the gain would read the loop's, near 1.
  const auto unaware = id.fit(r.commands, r.telemetry, v.equalised_s);
  REQUIRE(unaware.identified);
  CHECK(unaware.identified->inertia_gain == Approx(1.0).epsilon(0.1));
}

TEST_CASE("a fit without the data it needs is refused with the reason") {
  const RateResponseIdentifier id{RateLoopConfig{}};
  const Vehicle v{0.04, 1.0, 0.03, 0.0};
  SECTION("telemetry lost") {
    Recording r = fly(v, id, 3);
    r.telemetry.resize(r.telemetry.size() / 3);
    CHECK(id.fit(r.commands, r.telemetry, 0.03).refusal == IdentificationRefusal::no_telemetry);
    CHECK(id.fit({}, r.telemetry, 0.03).refusal == IdentificationRefusal::no_telemetry);
  }
  SECTION("the motors saturated") {
    Recording r = fly(v, id, 4);
    r.telemetry[r.telemetry.size() / 2].saturated = true;
    CHECK(id.fit(r.commands, r.telemetry, 0.03).refusal == IdentificationRefusal::saturated);
  }
  SECTION("no excitation flown") {
    const Recording r = fly(v, id, 5, 0.0);
    CHECK(id.fit(r.commands, r.telemetry, 0.03).refusal == IdentificationRefusal::no_motion);
  }
  SECTION("rates the loop cannot explain") {
    Recording r = fly(v, id, 6);
    std::mt19937 rng(6);
    std::normal_distribution<double> wild(0.0, 1.5);
    for (auto& s : r.telemetry) s.rate_radps += Eigen::Vector2d(wild(rng), wild(rng));
    const auto result = id.fit(r.commands, r.telemetry, 0.03);
    CHECK_FALSE(result.identified);
    CHECK(result.refusal != IdentificationRefusal::none);
  }
}

TEST_CASE("the excitation is a doublet on roll, then on pitch, and nothing outside it") {
  const RateResponseIdentifier id{RateLoopConfig{}};
  CHECK(id.excitation(-0.01).isZero());
  CHECK(id.excitation(0.05)[0] > 0.0);
  CHECK(id.excitation(0.17)[0] < 0.0);
  CHECK(id.excitation(0.3).isZero());
  CHECK(id.excitation(0.7)[1] > 0.0);
  CHECK(id.excitation(id.excitation_duration_s() + 0.01).isZero());
}

TEST_CASE("the fit in slices of 20 replays comes to the fit at once") {
  const RateResponseIdentifier id{RateLoopConfig{}};
  const Recording r = fly(Vehicle{0.05, 1.1, 0.03, 0.2}, id, 11);
  const auto whole = id.fit(r.commands, r.telemetry, 0.03);
  REQUIRE(whole.identified);
  gs::estimation::RateResponseFit sliced(id, r.commands, r.telemetry, 0.03);
  int slices = 1;
  while (!sliced.advance(20)) ++slices;
  CHECK(slices > 40);  // ~1100 replays
  REQUIRE(sliced.result()->identified);
  CHECK(sliced.result()->identified->time_constant_s == whole.identified->time_constant_s);
  CHECK(sliced.result()->identified->time_constant_high_s == whole.identified->time_constant_high_s);
}

TEST_CASE(
    "the ground station's copies of the rate loop and the airframe's thrust are the firmware's configuration") {
  const RateLoopConfig loop;
  const fw::RateControllerConfig rate;
  for (int axis = 0; axis < 2; ++axis) {
    CHECK(loop.kp_per_s[axis] == Approx(rate.kp_per_s[axis]));
    CHECK(loop.ki_per_s2[axis] == Approx(rate.ki_per_s2[axis]));
    CHECK(loop.integrator_limit_radps2[axis] == Approx(rate.integrator_limit_radps2[axis]));
  }
  CHECK(loop.rate_limit_radps == Approx(rate.rate_limit_radps));
  CHECK(loop.design_time_constant_s == Approx(fw::AirframeConfig{}.motor_time_constant_s));
  // The ground station's ceiling of a vehicle's thrust is the airframe's.
  const fw::AirframeConfig airframe;
  CHECK(gs::runtime::GroundStationConfig{}.airframe_thrust_max_mps2 ==
        Approx(4.0 * static_cast<double>(airframe.motor_thrust_max_N) / static_cast<double>(airframe.mass_kg))
            .epsilon(1e-6));
}
