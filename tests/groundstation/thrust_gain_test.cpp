// The thrust-gain estimator (groundstation/estimation/thrust_gain.hpp) on a vertical flight
// simulated here: a vehicle whose motors deliver k times the command, through a first-order lag,
// flown by a PD loop on noisy poses at 200 Hz with the commands acting 12 ms after they are sent.
#include <catch2/catch.hpp>

#include <cmath>
#include <functional>
#include <random>

#include "groundstation/estimation/thrust_gain.hpp"
#include "pa/constants.hpp"

namespace {

using gs::estimation::ThrustGainConfig;
using gs::estimation::ThrustGainEstimator;

struct Flight {
  std::function<double(double)> gain = [](double) { return 0.85; };  // the truth, over time
  double motor_time_constant_s = 0.03;
  double pose_noise_m = 0.0005;
  double body_z_up = 1.0;  // a tilted vehicle delivers along its z axis
  double load_mps2 = 0.0;  // an extra downward load (the pole), known to the estimator
  std::function<bool(double)> usable = [](double) { return true; };
  std::function<double(double)> push = [](double) { return 0.0; };  // unknown external m/s^2
  double climb_mps = 0.0;                                           // a steady climb
  bool voltage_compensated = false;  // the vehicle reports its pack's voltage and compensates for it
};

// Flies `seconds` and returns the estimator; the controller compensates with its estimate.
ThrustGainEstimator fly(const Flight& f, double seconds, std::uint64_t seed = 1) {
  ThrustGainEstimator estimator;
  estimator.set_voltage_compensated(f.voltage_compensated);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, f.pose_noise_m);
  const double dt = 0.001, lead = 0.012;
  double z = 1.0, vz = 0.0, thrust = pa::kGravity_mps2, command = pa::kGravity_mps2;
  std::vector<std::pair<double, double>> in_flight;  // commands on their way
  for (int i = 0; i * dt < seconds; ++i) {
    const double t = i * dt;
    // 200 Hz: a pose, and a command that acts `lead` later (a gentle sine in height to excite).
    if (i % 5 == 0) {
      estimator.pose(t, z + noise(rng), f.body_z_up, f.load_mps2, f.usable(t));
      const double z_ref = 1.0 + f.climb_mps * t + 0.2 * std::sin(0.7 * t);
      const double a = 6.0 * (z_ref - z) - 4.0 * (vz - f.climb_mps) + pa::kGravity_mps2 + f.load_mps2;
      const double sent = a / (estimator.gain() * f.body_z_up);
      in_flight.push_back({t + lead, sent});
      estimator.command(t + lead, sent);
    }
    while (!in_flight.empty() && in_flight.front().first <= t) {
      command = in_flight.front().second;
      in_flight.erase(in_flight.begin());
    }
    thrust += (command - thrust) * dt / f.motor_time_constant_s;
    const double az = f.gain(t) * thrust * f.body_z_up - pa::kGravity_mps2 - f.load_mps2 + f.push(t);
    vz += az * dt;
    z += vz * dt;
  }
  return estimator;
}

}  // namespace

TEST_CASE("A weak vehicle's gain is found within 1 % in 10 s of flight") {
  for (double k : {0.85, 1.0, 1.1}) {
    Flight f;
    f.gain = [k](double) { return k; };
    const ThrustGainEstimator e = fly(f, 10.0);
    CAPTURE(k, e.gain(), e.sigma(), e.measurements(), e.rejected());
    CHECK(std::abs(e.gain() - k) < 0.01 * k);
    CHECK(e.sigma() < 0.01);
    CHECK(e.measurements() > 90);
  }
}

TEST_CASE("A draining pack is followed within 2 % throughout") {
  Flight f;
  f.gain = [](double t) { return 1.0 - 0.2 * t / 300.0; };  // a fifth of the thrust in 5 minutes
  ThrustGainEstimator e = fly(f, 20.0);
  for (double t : {60.0, 150.0, 300.0}) {
    e = fly(f, t, 7);
    CAPTURE(t, e.gain(), f.gain(t));
    CHECK(std::abs(e.gain() - f.gain(t)) < 0.02 * f.gain(t));
  }
}

TEST_CASE("A vehicle that compensates its pack's voltage is taken to drift less, so k is held steadier") {
  Flight f;
  f.gain = [](double) { return 0.9; };
  const ThrustGainEstimator plain = fly(f, 120.0, 3);
  f.voltage_compensated = true;
  const ThrustGainEstimator compensated = fly(f, 120.0, 3);
  CAPTURE(plain.gain(), plain.sigma(), compensated.gain(), compensated.sigma());
  CHECK(std::abs(compensated.gain() - 0.9) < 0.01 * 0.9);
  // The steady uncertainty goes with the square root of the drift (1e-3 against 3e-3).
  CHECK(compensated.sigma() < 0.7 * plain.sigma());
}

TEST_CASE("Tilt, a known load and motors slower than the airframe file's are accounted for") {
  Flight f;
  f.body_z_up = std::cos(0.3);
  f.load_mps2 = 0.57;  // the pole's weight over the vehicle's mass
  f.motor_time_constant_s = 0.06;
  const ThrustGainEstimator e = fly(f, 10.0);
  CAPTURE(e.gain());
  CHECK(std::abs(e.gain() - 0.85) < 0.01);
}

TEST_CASE("Unusable poses and disturbances do not move the estimate") {
  Flight grounded;
  grounded.usable = [](double) { return false; };
  const ThrustGainEstimator none = fly(grounded, 5.0);
  CHECK(none.measurements() == 0);
  CHECK(none.gain() == 1.0);
  // Knocks of 20 m/s^2 for 20 ms every 2 s (the pole bumping the plate): skipped.
  Flight knocked;
  knocked.push = [](double t) { return std::fmod(t, 2.0) < 0.02 ? 20.0 : 0.0; };
  const ThrustGainEstimator e = fly(knocked, 20.0);
  CAPTURE(e.gain(), e.rejected());
  CHECK(e.rejected() > 0);
  CHECK(std::abs(e.gain() - 0.85) < 0.01);
}

TEST_CASE("A jolt before the first measurement does not move the estimate from the airframe file's") {
  // While the estimate still has the airframe file's 10 %, the gate is wide: a window where the
  // vehicle was turned from sinking to climbing at 3.5 m/s^2 on the thrust of hover (a bump: a
  // weak vehicle stalling in its take-off showed 5.1) passed it as the first measurement and
  // moved k by a quarter.
  ThrustGainEstimator e;
  for (int i = 0; i <= 60; ++i) {
    const double t = 0.005 * i;
    e.command(t, pa::kGravity_mps2);
    const double z = t > 0.1 ? 1.0 : 1.0 - 0.175 * t + 1.75 * t * t;  // the bump: the first window
    e.pose(t, z, 1.0, 0.0, true);
  }
  CAPTURE(e.gain(), e.rejected(), e.measurements());
  CHECK(e.rejected() > 0);
  CHECK(std::abs(e.gain() - 1.0) < 0.01);  // it was 1.28
}

TEST_CASE("A climbing or sinking vehicle is not measured (its drag is not in the model)") {
  Flight climbing;
  climbing.climb_mps = 0.5;
  const ThrustGainEstimator e = fly(climbing, 5.0);
  CHECK(e.measurements() <= 2);  // of some 50 windows: only while it gathers speed at the start
  CHECK(fly(Flight{}, 5.0).measurements() > 40);
}

TEST_CASE("Bad input is ignored: non-finite values, time going back") {
  ThrustGainEstimator e;
  e.command(std::nan(""), 9.81);
  e.command(0.0, std::numeric_limits<double>::infinity());
  e.pose(std::nan(""), 1.0, 1.0, 0.0, true);
  e.pose(0.0, std::nan(""), 1.0, 0.0, true);
  e.command(0.01, 9.81);
  for (int i = 0; i < 40; ++i) e.pose(0.01 + 0.005 * i, 1.0, 1.0, 0.0, true);
  e.pose(0.0, 1.0, 1.0, 0.0, true);  // back in time: the window restarts
  CHECK(std::isfinite(e.gain()));
  CHECK(e.gain() >= 0.5);
  CHECK(e.gain() <= 1.5);
}
