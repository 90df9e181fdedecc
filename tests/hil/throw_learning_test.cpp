// The throw learnt from past trials (groundstation/adaptation/throw_learning.hpp) in the closed
// loop: vehicle 1's motors 5 % weak and the drag 30 % high (the vehicles' and the pole's), ten
// throws without catches; the launch-state error the ground station measures (its estimate of
// the thrower's end state against the plan's, |e| in SI units) by the 8th to 10th throws is at
// most 0.6 of the same throws' without the learning, which stays above half the first throw's.
// The correction's algebra is checked on its own first.
#include "groundstation/adaptation/throw_learning.hpp"

#include <catch2/catch.hpp>
#include <cstdio>
#include <vector>

#include "groundstation/planning/throw_correction.hpp"
#include "hil/trials/series.hpp"

namespace {

using gs::adaptation::LaunchVector;
using gs::adaptation::ThrowCorrection;
using gs::adaptation::ThrowLearningSettings;

const gs::adaptation::LaunchMatrix kIdentity = gs::adaptation::LaunchMatrix::Identity();

// The launch errors of ten throw-only attempts, as the ground station measured them.
std::vector<LaunchVector> launch_errors(double gain) {
  hil::trials::SeriesConfig config;
  config.seed = 5;
  config.attempt_timeout_s = 20.0;
  for (int m = 0; m < 4; ++m) config.plant.vehicle.motor_gain[0][m] = 0.95;
  config.plant.vehicle.drag_Nspm *= 1.3;
  config.plant.pole.drag_axial_kgpm2 *= 1.3;
  config.plant.pole.drag_normal_kgpm2 *= 1.3;
  config.plant.pole.drag_rotational_kgpm2 *= 1.3;
  config.ground_station.learning.throw_learning.gain = gain;
  hil::trials::SeriesRunner runner(config);
  runner.run(std::vector<hil::trials::AttemptPlan>(
      10, hil::trials::AttemptPlan{false, Eigen::Vector2d::Zero(), 0.0}));
  std::vector<LaunchVector> errors;
  for (const gs::runtime::AttemptReport& a : runner.ground_station().attempts())
    if (a.launch_error) errors.push_back(*a.launch_error);
  return errors;
}

void print(const char* what, const std::vector<LaunchVector>& errors) {
  std::printf("%s: launch-state error |e| per throw (x, z m; x', z' m/s; alpha rad; alpha' rad/s):\n", what);
  for (std::size_t i = 0; i < errors.size(); ++i) {
    const LaunchVector& e = errors[i];
    std::printf("  throw %2zu  |e| %.3f   (%+.3f %+.3f %+.3f %+.3f %+.3f %+.3f)\n", i + 1, e.norm(), e(0),
                e(1), e(2), e(3), e(4), e(5));
  }
}

}  // namespace

TEST_CASE("a throw's launch error moves the correction against it, within bounds", "[throw_learning]") {
  ThrowLearningSettings settings;
  const gs::planning::PlanarLaunchState planned = gs::planning::fig5_launch_state();
  gs::planning::PlanarLaunchState flown = planned;
  flown.vz_mps -= 0.2;
  flown.alpha_rad += 0.02;
  const ThrowCorrection once = gs::adaptation::learn_from_throw({}, flown, planned, settings, kIdentity);
  CHECK(once.throws == 1);
  CHECK(once.end_shift(3) == Approx(0.1));
  CHECK(once.end_shift(4) == Approx(-0.01));
  CHECK(once.end_shift(0) == 0.0);
  // Repeated, the correction is bounded.
  ThrowCorrection c;
  for (int i = 0; i < 100; ++i) c = gs::adaptation::learn_from_throw(c, flown, planned, settings, kIdentity);
  CHECK(c.end_shift(3) == Approx(settings.max_speed_mps));
  // A spoiled throw (an error beyond a bound) teaches nothing.
  flown.x_m += 0.5;
  CHECK(gs::adaptation::learn_from_throw(once, flown, planned, settings, kIdentity).end_shift ==
        once.end_shift);
  // The reference shift is zero at the throw's start and the whole correction at its end.
  CHECK(gs::planning::reference_shift(once.end_shift, 0.0, 2.5).isZero());
  CHECK(gs::planning::reference_shift(once.end_shift, 2.5, 2.5)(gs::model::planar::kVz) == Approx(0.1));
  CHECK(gs::planning::reference_shift(once.end_shift, 1.25, 2.5)(gs::model::planar::kVz) == Approx(0.05));
}

TEST_CASE("with weak motors and high drag the learning takes 40 % off the launch error after 10 throws",
          "[hil][sil][runtime][throw_learning]") {
  const std::vector<LaunchVector> learning = launch_errors(0.5);
  const std::vector<LaunchVector> fixed = launch_errors(0.0);
  print("learning (gain 0.5)", learning);
  print("not learning", fixed);
  REQUIRE(learning.size() == 10);
  REQUIRE(fixed.size() == 10);
  // After 10 throws: the mean of the 8th to the 10th, as one throw's error has a random part of
  // a few hundredths (the spread of the unlearnt throws) beside the plant's repeating one.
  const auto late = [](const std::vector<LaunchVector>& e) {
    return (e[7].norm() + e[8].norm() + e[9].norm()) / 3.0;
  };
  std::printf("mean |e| of throws 8-10: %.3f learning, %.3f not (first throw %.3f)\n", late(learning),
              late(fixed), learning.front().norm());
  // Measured: 0.097 learning, 0.172 not. While the setpoints stopped at a_q,max (before the
  // airframe's full thrust, GroundStationConfig::airframe_thrust_max_mps2), the weak motors fell
  // short at the throw's peak and that repeated: 0.074 learning, 0.205 not. The thrust gain now
  // gives them what they miss, so less of the error repeats and the learning has less to take.
  CHECK(late(learning) <= 0.6 * late(fixed));
  // Without the learning the error stays: what the learning removed was the plant's, not chance.
  CHECK(late(fixed) > 0.5 * fixed.front().norm());
}
