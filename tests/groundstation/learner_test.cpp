// The learner (groundstation/adaptation/learner.hpp): the gate against the in-flight prediction,
// odd throws, the catching instant's mean, the throw learnt from its launch errors, the miss of
// throws to targets, and a restart that continues from the store's history.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "adaptation_test_support.hpp"
#include "groundstation/adaptation/learner.hpp"

namespace {

using namespace gs::adaptation;

AdaptationSettings settings() {
  AdaptationSettings s;
  s.nominal_catch_height_m = -0.6;
  s.nominal_waiting_xy_m = Eigen::Vector2d(3.5, 0.0);
  s.target_energy_J = 0.196;
  return s;
}

const gs::planning::PlanarLaunchState kPlanned{1.5, 2.0, 0.3, 5.5, 0.48, 2.5};

Learner learner(const LearnerSettings& s = {}, const std::string& store = "") {
  return Learner(s, settings(), 0.8, kPlanned, LaunchMatrix::Identity(), std::nullopt, store);
}

OptimalCatch catch_at(double height_m, double x_m, double t_s) {
  return {t_s, height_m, Eigen::Vector2d(x_m, 0.0)};
}

// A throw caught where `o` says, at its waiting point.
ThrowRecord caught(const OptimalCatch& o) {
  ThrowRecord r;
  r.time_s = 10.0;
  r.outcome = ThrowOutcome::caught;
  r.launch = kPlanned;
  r.catch_height_used_m = o.height_m;
  r.waiting_xy_m = o.xy_m;
  r.target_xy_m = o.xy_m;
  r.catcher_at_impact_xy_m = o.xy_m;
  return r;
}

// The evaluated catch `o` learnt as a Fig. 5 throw's, then adapted to.
ThrowRecord throw_with(Learner& l, const OptimalCatch& o) {
  ThrowRecord r = caught(o);
  l.learn_optimal_catch(r, o, true);
  l.adapt(r);
  return r;
}

}  // namespace

TEST_CASE("An evaluation agrees with its prediction within the gate, in height, place and time") {
  const Learner l = learner();
  const OptimalCatch p = catch_at(-0.6, 3.5, 0.8);
  CHECK(l.evaluation_agrees(catch_at(-0.61, 3.55, 0.85), p));
  CHECK_FALSE(l.evaluation_agrees(catch_at(-0.85, 3.5, 0.8), p));
  CHECK_FALSE(l.evaluation_agrees(catch_at(-0.6, 3.75, 0.8), p));
  CHECK_FALSE(l.evaluation_agrees(catch_at(-0.6, 3.5, 0.95), p));
  CHECK_FALSE(l.evaluation_agrees(p, std::nullopt));
}

TEST_CASE("Gated samples move the catching instant's mean; a rejected one is noted in the record") {
  Learner l = learner();
  ThrowRecord r = caught(catch_at(-0.6, 3.5, 0.9));
  l.learn_optimal_catch(r, catch_at(-0.6, 3.5, 0.9), false);
  CHECK_FALSE(r.optimal);
  CHECK(r.note.find("rejected") != std::string::npos);
  CHECK(l.catch_instant_s() == 0.8);
  throw_with(l, catch_at(-0.6, 3.5, 0.9));
  throw_with(l, catch_at(-0.6, 3.5, 1.0));
  CHECK(l.catch_instant_s() == Approx(0.95));
  CHECK(l.state().catch_point_samples == 2);
  CHECK(l.records().size() == 2);
}

TEST_CASE("An odd throw counts only once such throws repeat") {
  LearnerSettings s;
  s.outlier_repeats = 3;
  Learner l = learner(s);
  throw_with(l, catch_at(-0.6, 3.5, 0.8));
  const OptimalCatch odd = catch_at(-0.6, 4.2, 0.8);  // 0.7 m away, beyond outlier_m
  CHECK_FALSE(throw_with(l, odd).optimal);
  CHECK_FALSE(throw_with(l, odd).optimal);
  CHECK(l.state().waiting_xy_m.x() == Approx(3.5));
  CHECK(throw_with(l, odd).optimal);  // the third in a row: the system has changed
  CHECK(l.state().waiting_xy_m.x() > 3.5);
  // A throw near the mean again resets the count.
  Learner m = learner(s);
  throw_with(m, catch_at(-0.6, 3.5, 0.8));
  CHECK_FALSE(throw_with(m, odd).optimal);
  CHECK(throw_with(m, catch_at(-0.6, 3.6, 0.8)).optimal);
  CHECK_FALSE(throw_with(m, odd).optimal);
}

TEST_CASE("A record that fails validation is kept but not adapted to") {
  Learner l = learner();
  ThrowRecord r = caught(catch_at(-0.6, 3.5, 0.8));
  r.optimal = catch_at(std::numeric_limits<double>::quiet_NaN(), 3.5, 0.8);
  const AdaptationState before = l.state();
  l.adapt(r);
  CHECK(l.state() == before);
  CHECK(l.records().size() == 1);
  l.keep(caught(catch_at(-0.6, 3.5, 0.8)));  // a throw to a target: kept only
  CHECK(l.state() == before);
  CHECK(l.records().size() == 2);
}

TEST_CASE("The launch error is learnt only with a gain, against the error") {
  LearnerSettings off;
  off.throw_learning.gain = 0.0;
  Learner none = learner(off);
  gs::planning::PlanarLaunchState flown = kPlanned;
  flown.x_m += 0.05;
  none.learn_launch(pa::kVehicle1, flown);
  CHECK(none.throw_correction(pa::kVehicle1).end_shift.isZero());
  Learner l = learner();
  l.learn_launch(pa::kVehicle1, flown);
  CHECK(l.throw_correction(pa::kVehicle1).throws == 1);
  CHECK(l.throw_correction(pa::kVehicle1).end_shift(0) < 0.0);
}

TEST_CASE("Each vehicle learns its own throw, and a restart rebuilds both from the store") {
  adaptation_test::ScratchDir dir("learner_throwers");
  const std::string path = dir.file("store.db");
  gs::planning::PlanarLaunchState short_throw = kPlanned;
  short_throw.vz_mps -= 0.3;
  gs::planning::PlanarLaunchState long_throw = kPlanned;
  long_throw.vz_mps += 0.2;
  Learnt before;
  {
    Learner l = learner({}, path);
    for (int i = 0; i < 2; ++i) {
      ThrowRecord r = caught(catch_at(-0.6, 3.5, 0.8));
      r.thrower = pa::kActVehicles[i];
      r.launch = i == 0 ? short_throw : long_throw;
      l.learn_launch(*r.thrower, r.launch);
      l.adapt(r);
    }
    // Vehicle 1 threw short and vehicle 2 long: their corrections pull opposite ways.
    CHECK(l.throw_correction(pa::kVehicle1).throws == 1);
    CHECK(l.throw_correction(pa::kVehicle2).throws == 1);
    CHECK(l.throw_correction(pa::kVehicle1).end_shift(3) > 0.0);
    CHECK(l.throw_correction(pa::kVehicle2).end_shift(3) < 0.0);
    before = l.learnt();
  }
  const Learner restarted = learner({}, path);
  for (const pa::VehicleId v : pa::kActVehicles) {
    CHECK(restarted.throw_correction(v).throws == 1);
    CHECK(restarted.throw_correction(v).end_shift.isApprox(
        before.throw_corrections[pa::act_slot(v)].end_shift));
  }
}

TEST_CASE("The miss of throws to targets is their mean, outliers aside") {
  Learner l = learner();
  l.learn_target_miss(Eigen::Vector3d(0.1, 0.0, 0.0));
  l.learn_target_miss(Eigen::Vector3d(0.2, 0.0, 0.1));
  l.learn_target_miss(Eigen::Vector3d(0.0, 0.9, 0.0));  // beyond outlier_m
  CHECK(l.target_miss_m().isApprox(Eigen::Vector3d(0.15, 0.0, 0.05)));
}

TEST_CASE("A learner on a store continues after a restart where the last one stopped") {
  adaptation_test::ScratchDir dir("learner");
  const std::string path = dir.file("store.db");
  Learnt before;
  {
    Learner l = learner({}, path);
    throw_with(l, catch_at(-0.6, 3.5, 0.9));
    gs::planning::PlanarLaunchState flown = kPlanned;
    flown.z_m -= 0.04;
    l.learn_launch(pa::kVehicle1, flown);
    ThrowRecord r = throw_with(l, catch_at(-0.5, 3.6, 1.0));
    before = l.learnt();
    CHECK(before.state.catch_point_samples == 2);
  }
  const Learner restarted = learner({}, path);
  CHECK(restarted.state() == before.state);
  CHECK(restarted.catch_instant_s() == Approx(before.catch_instant_s));
  CHECK(restarted.records().empty());
}
