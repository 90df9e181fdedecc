// The catching height corrected per catcher from the energy after each impact
// (groundstation/adaptation/catch_energy.hpp).
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <random>

#include "groundstation/adaptation/catch_energy.hpp"

using gs::adaptation::CatchEnergyCorrection;
using gs::adaptation::CatchEnergySettings;

namespace {
constexpr double kTarget_J = 0.196;  // E* of the paper's pole
}

TEST_CASE("Too much energy raises the catcher's catch, too little lowers it; each catcher its own") {
  CatchEnergyCorrection c;
  CHECK(c.height_offset_m(pa::kVehicle1) == 0.0);
  REQUIRE(c.learn(pa::kVehicle2, kTarget_J + 0.018, kTarget_J));
  CHECK(c.height_offset_m(pa::kVehicle2) == Approx(0.5 * 0.018 / 0.09));  // 0.1 m higher
  CHECK(c.height_offset_m(pa::kVehicle1) == 0.0);
  REQUIRE(c.learn(pa::kVehicle1, kTarget_J - 0.009, kTarget_J));
  CHECK(c.height_offset_m(pa::kVehicle1) == Approx(-0.05));
}

TEST_CASE("What is not a catch gone slightly off is not learnt, and the offset is bounded") {
  CatchEnergyCorrection c;
  CHECK_FALSE(c.learn(pa::kVehicle1, std::numeric_limits<double>::quiet_NaN(), kTarget_J));
  CHECK_FALSE(c.learn(pa::kVehicle1, kTarget_J + 0.2, kTarget_J));
  CHECK_FALSE(c.learn(pa::VehicleId(7), kTarget_J + 0.01, kTarget_J));
  CHECK(c.height_offset_m(pa::kVehicle1) == 0.0);
  CHECK(c.height_offset_m(pa::VehicleId(7)) == 0.0);
  for (int i = 0; i < 50; ++i) REQUIRE(c.learn(pa::kVehicle1, kTarget_J + 0.07, kTarget_J));
  CHECK(c.height_offset_m(pa::kVehicle1) == Approx(CatchEnergySettings{}.max_offset_m));
}

TEST_CASE("On a catcher whose energy follows the height with another sensitivity, the offset converges") {
  // E(h) = E* + s' (h* - h) with noise: the catcher should catch h* = 0.2 m higher than it does.
  for (const double true_sensitivity : {0.03, 0.09, 0.25}) {
    CAPTURE(true_sensitivity);
    CatchEnergyCorrection c;
    std::mt19937 rng(3);
    std::normal_distribution<double> noise(0.0, 0.003);
    double error_m = 0.0;
    for (int i = 0; i < 60; ++i) {
      const double h = c.height_offset_m(pa::kVehicle2);
      REQUIRE(c.learn(pa::kVehicle2, kTarget_J + true_sensitivity * (0.2 - h) + noise(rng), kTarget_J));
      error_m = std::abs(c.height_offset_m(pa::kVehicle2) - 0.2);
    }
    // The noise's share: 0.003 J over the sensitivity, times the averaging.
    CHECK(error_m < 0.03 + 0.003 / true_sensitivity);
  }
}
