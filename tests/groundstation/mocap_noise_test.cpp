// The motion capture's noise read off the poses' second differences: on a hovering, swaying
// body it finds the noise drawn, whatever the motion; throws, gaps and bad poses do not count.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <random>

#include "groundstation/estimation/mocap_noise.hpp"

using gs::estimation::MocapNoiseMeter;
using gs::estimation::MocapPose;

namespace {

constexpr double kPeriod_s = 0.005;

// A vehicle hovering and swaying (5 cm, 0.1 rad at 0.5 Hz), seen with noise of the given sigmas
// (position per axis; attitude a small rotation about a random body axis, per axis).
MocapPose hovering(double t_s, double position_sigma_m, double attitude_sigma_rad, std::mt19937& rng) {
  std::normal_distribution<double> unit(0.0, 1.0);
  const double w = 2.0 * M_PI * 0.5;
  MocapPose pose;
  pose.p_m = Eigen::Vector3d(0.05 * std::sin(w * t_s), 0.02 * std::cos(w * t_s), 1.5) +
             position_sigma_m * Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
  const Eigen::Quaterniond truth(Eigen::AngleAxisd(0.1 * std::sin(w * t_s), Eigen::Vector3d::UnitX()));
  const Eigen::Vector3d noise = attitude_sigma_rad * Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
  pose.q = truth * Eigen::Quaterniond(Eigen::AngleAxisd(noise.norm(), noise.normalized()));
  return pose;
}

}  // namespace

TEST_CASE("the meter finds the noise a hovering, swaying body is seen with") {
  for (const double sigma : {0.5e-3, 1e-3, 3e-3}) {
    std::mt19937 rng(7);
    MocapNoiseMeter meter(kPeriod_s);
    for (int k = 0; k < 2000; ++k)
      meter.add(k * kPeriod_s, hovering(k * kPeriod_s, sigma, 2.0 * sigma, rng), true);
    const auto noise = meter.noise();
    REQUIRE(noise);
    CHECK(noise->position_sigma_m == Approx(sigma).epsilon(0.1));
    CHECK(noise->attitude_sigma_rad == Approx(2.0 * sigma).epsilon(0.1));
  }
}

TEST_CASE("the meter waits for enough frames and counts only three in a row, quiet and finite") {
  std::mt19937 rng(3);
  MocapNoiseMeter meter(kPeriod_s);
  // Every other frame missing: no run of three one period apart.
  for (int k = 0; k < 4000; k += 2) meter.add(k * kPeriod_s, hovering(k * kPeriod_s, 1e-3, 1e-3, rng), true);
  CHECK(meter.samples() == 0);
  CHECK_FALSE(meter.noise());
  // A throw (not quiet) and broken poses start the run over and add nothing.
  MocapPose broken = hovering(0.0, 1e-3, 1e-3, rng);
  broken.p_m.x() = std::numeric_limits<double>::quiet_NaN();
  for (int k = 0; k < 100; ++k) {
    const double t = 30.0 + k * kPeriod_s;
    meter.add(t, k % 3 == 2 ? broken : hovering(t, 1e-3, 1e-3, rng), k % 5 != 4);
  }
  CHECK(meter.samples() == 0);
  // Then a steady run: three per frame after the first two, and an estimate at the minimum.
  for (int k = 0; k < 202; ++k)
    meter.add(40.0 + k * kPeriod_s, hovering(40.0 + k * kPeriod_s, 1e-3, 1e-3, rng), true);
  CHECK(meter.samples() == 3 * 200);
  CHECK(meter.noise());
}

TEST_CASE("a few bursts of hard acceleration hardly move the estimate") {
  std::mt19937 rng(11);
  MocapNoiseMeter meter(kPeriod_s);
  for (int k = 0; k < 2000; ++k) {
    MocapPose pose = hovering(k * kPeriod_s, 1e-3, 1e-3, rng);
    if (k % 20 == 0) pose.p_m.z() += 0.02;  // one frame in 20 off by 2 cm
    meter.add(k * kPeriod_s, pose, true);
  }
  const auto noise = meter.noise();
  REQUIRE(noise);
  CHECK(noise->position_sigma_m == Approx(1e-3).epsilon(0.25));
}
