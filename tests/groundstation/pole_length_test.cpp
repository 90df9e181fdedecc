// The pole's half length from motion capture (groundstation/estimation/pole_length.hpp): the
// geometry of one sample on a tilted, turned vehicle, the poses it refuses, and the learner's
// mean, its threshold and its consistency gate.
#include "groundstation/estimation/pole_length.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "pa/constants.hpp"

namespace {

using Eigen::AngleAxisd;
using Eigen::Quaterniond;
using Eigen::Vector3d;
using gs::estimation::MocapPose;
using gs::estimation::pole_half_length_sample;
using gs::estimation::PoleLengthLearner;
using gs::estimation::PoleLengthParams;

constexpr double kPlateHeight = pa::kPlateHeightAboveCg_m;

// A vehicle at (1, 2, 3) rolled 0.2 rad, pitched -0.1 rad and turned 0.7 rad.
MocapPose tilted_vehicle() {
  MocapPose v;
  v.p_m = Vector3d(1.0, 2.0, 3.0);
  v.q = AngleAxisd(0.7, Vector3d::UnitZ()) * AngleAxisd(-0.1, Vector3d::UnitY()) *
        AngleAxisd(0.2, Vector3d::UnitX());
  return v;
}

// A pole of half length L whose lower end rests on the vehicle's plate at `offset` (plate frame)
// and whose axis leans `lean` rad from the plate's normal; `flipped` reports n downwards.
MocapPose pole_on(const MocapPose& vehicle, double length_m, const Vector3d& offset, double lean,
                  bool flipped) {
  const Vector3d lower_end = vehicle.p_m + vehicle.q * (Vector3d(0.0, 0.0, kPlateHeight) + offset);
  const Quaterniond up = vehicle.q * AngleAxisd(lean, Vector3d(1.0, 1.0, 0.0).normalized());
  MocapPose p;
  p.p_m = lower_end + length_m * (up * Vector3d::UnitZ());
  p.q = flipped ? up * AngleAxisd(M_PI, Vector3d::UnitX()) : up;
  return p;
}

}  // namespace

TEST_CASE("one sample is the pole centre's height over the plate's plane along the pole", "[pole_length]") {
  const MocapPose v = tilted_vehicle();
  for (const bool flipped : {false, true}) {
    for (const double lean : {0.0, 0.15, 0.3}) {
      const std::optional<double> l = pole_half_length_sample(
          v, pole_on(v, 0.652, Vector3d(0.03, -0.02, 0.0), lean, flipped), kPlateHeight, {});
      REQUIRE(l);
      CHECK(*l == Approx(0.652).margin(1e-9));
    }
  }
}

TEST_CASE("a pole that is not resting upright on this plate gives no sample", "[pole_length]") {
  const MocapPose v = tilted_vehicle();
  const PoleLengthParams params;
  // Leaning beyond max_axis_tilt_rad (a pole swinging up after the catch, or falling).
  CHECK_FALSE(
      pole_half_length_sample(v, pole_on(v, 0.665, Vector3d::Zero(), 0.5, false), kPlateHeight, params));
  // Its end beside the plate.
  CHECK_FALSE(pole_half_length_sample(v, pole_on(v, 0.665, Vector3d(0.2, 0.0, 0.0), 0.0, false), kPlateHeight,
                                      params));
  // Lifted 10 cm off the plate (a launch): the length it implies is not a pole's.
  CHECK_FALSE(pole_half_length_sample(v, pole_on(v, 0.665, Vector3d(0.0, 0.0, 0.1), 0.0, false), kPlateHeight,
                                      params));
  // A glitch in the motion capture.
  MocapPose glitch = pole_on(v, 0.665, Vector3d::Zero(), 0.0, false);
  glitch.p_m.x() = std::nan("");
  CHECK_FALSE(pole_half_length_sample(v, glitch, kPlateHeight, params));
}

TEST_CASE("the learner gives the mean of its samples (learnt once it has enough), and ignores outliers",
          "[pole_length]") {
  PoleLengthParams params;
  PoleLengthLearner learner(params);
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.002);
  CHECK_FALSE(learner.estimate());
  REQUIRE(learner.add(0.657));
  CHECK(*learner.estimate() == 0.657);  // the filters fly on it before it is learnt
  for (int i = 1; i < params.samples_to_learn - 1; ++i) REQUIRE(learner.add(0.655 + noise(rng)));
  CHECK_FALSE(learner.learnt());
  CHECK(*learner.estimate() == Approx(0.655).margin(0.001));
  REQUIRE(learner.add(0.655 + noise(rng)));
  REQUIRE(learner.learnt());
  CHECK(*learner.learnt() == Approx(0.655).margin(0.0005));

  // Once learnt, a sample 3 cm off (a bounce) is refused and changes nothing.
  const double before = *learner.learnt();
  CHECK_FALSE(learner.add(0.685));
  CHECK(*learner.learnt() == before);
  // Never a length far from the nominal, nor a non-finite one.
  PoleLengthLearner fresh(params);
  CHECK_FALSE(fresh.add(0.9));
  CHECK_FALSE(fresh.add(std::nan("")));
  CHECK(fresh.samples() == 0);
}

TEST_CASE("after max_samples the learner is a moving average that follows a slow change", "[pole_length]") {
  PoleLengthParams params;
  params.max_samples = 100;
  params.samples_to_learn = 10;
  PoleLengthLearner learner(params);
  for (int i = 0; i < 1000; ++i) learner.add(0.660);
  // The absorber settles by 5 mm, within the consistency gate.
  for (int i = 0; i < 1000; ++i) learner.add(0.665);
  CHECK(learner.samples() == 100);
  CHECK(*learner.learnt() == Approx(0.665).margin(1e-4));
}
