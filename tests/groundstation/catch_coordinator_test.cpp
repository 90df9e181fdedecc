// The catch coordinator (groundstation/runtime/catch_coordinator.hpp) on the Fig. 5 throw's
// pole in free flight: when the catch is due, the catch point followed, the verdicts judged only
// once the prediction has converged, the retiming bounded and the catch window.
#include <catch2/catch.hpp>

#include "groundstation/planning/catching_instant.hpp"
#include "groundstation/runtime/catch_coordinator.hpp"
#include "pa/constants.hpp"

namespace {

using gs::mission::Task;
using gs::runtime::AttemptReport;
using gs::runtime::CatchCoordinator;
using gs::runtime::CatchSettings;
using gs::runtime::CatchView;

const gs::model::PoleParams kPole;

// The Fig. 5 pole just after the launch at t = 10 s, and its optimal catch (42).
struct Throw {
  gs::model::PoleState pole = gs::planning::pole_state_at_launch(gs::planning::fig5_launch_state(), kPole);
  gs::planning::CatchingInstant optimal = gs::planning::find_catching_instant(pole, kPole);
  double launch_s = 10.0;
};

// The catcher in `task` seeing the pole in free flight, launched `after_s` ago.
CatchView view(const Throw& t, Task task, double after_s) {
  CatchView v;
  v.catcher_task = task;
  v.pole.valid = true;
  v.pole.mode = gs::estimation::PoleMode::free;
  v.pole.t_s = t.launch_s + after_s;
  v.pole.state = t.pole;  // the prediction starts from the launch state whenever it is asked
  v.pole_model = kPole;
  v.catcher_position_m = Eigen::Vector3d(t.optimal.catch_point_m.x(), 0.0, 2.0);
  return v;
}

// An attempt whose catcher waits `off_m` along x from the optimal catch point.
AttemptReport waiting(const Throw& t, double off_m) {
  AttemptReport r;
  r.waiting_xy_m = t.optimal.catch_point_m + Eigen::Vector2d(off_m, 0.0);
  r.catch_height_m = t.optimal.catch_height_m;
  return r;
}

}  // namespace

TEST_CASE("The catch is due when the z manoeuvre must start to end at the catching instant") {
  const Throw t;
  REQUIRE(t.optimal.found);
  CatchCoordinator c(CatchSettings{}, {});
  const AttemptReport r = waiting(t, 0.0);
  c.plan(r, t.launch_s, t.optimal.t_s);
  const double t_z = c.z_manoeuvre(r.catch_height_m).duration_s();
  CHECK(t_z > 1.0);
  CHECK(c.start_s() == Approx(t.launch_s + t.optimal.t_s - t_z));
  CHECK_FALSE(c.due(c.start_s() - 0.001));
  CHECK(c.due(c.start_s()));
  CHECK(c.target_xy_m() == r.waiting_xy_m);
  // Started late, the catch keeps its planned start; started early, it starts now. The window
  // covers the manoeuvre's rest and the margin.
  const double planned = c.start_s();
  CHECK(c.start(planned + 0.1, r.catch_height_m, 1.0) == Approx(t_z - 0.1 + 1.0));
  CHECK(c.start_s() == planned);
  CHECK(c.start(planned - 0.2, r.catch_height_m, 1.0) == Approx(t_z + 1.0));
  CHECK(c.start_s() == planned - 0.2);
}

TEST_CASE("The catch follows the predicted catch point; verdicts wait for the prediction to converge") {
  const Throw t;
  const CatchSettings s;
  CatchCoordinator c(s, {});
  AttemptReport r = waiting(t, 0.0);
  c.plan(r, t.launch_s, t.optimal.t_s);
  r.launch_s = t.launch_s;
  c.update(t.launch_s + 0.05, view(t, Task::wait, 0.05), r);
  REQUIRE(r.predicted);
  CHECK((c.target_xy_m() - t.optimal.catch_point_m).norm() < 0.01);
  CHECK(r.last_target_xy_m == c.target_xy_m());
  CHECK_FALSE(r.converged_prediction);
  c.update(t.launch_s + s.verdict_delay_s + 0.001, view(t, Task::wait, s.verdict_delay_s), r);
  CHECK(r.converged_prediction);
  CHECK_FALSE(c.unreachable());
  CHECK_FALSE(c.infeasible());
  CHECK_FALSE(c.trajectory());  // planned only once catching
  c.update(t.launch_s + 0.2, view(t, Task::catching, 0.2), r);
  REQUIRE(c.trajectory());
  CHECK(c.trajectory()->duration_s() == Approx(c.z_manoeuvre(r.catch_height_m).duration_s()));
  // The catch's practice offset moves the target with it.
  CatchView offset = view(t, Task::catching, 0.25);
  offset.catch_offset_m = Eigen::Vector2d(0.0, 0.3);
  c.update(t.launch_s + 0.25, offset, r);
  CHECK((c.target_xy_m() - t.optimal.catch_point_m - offset.catch_offset_m).norm() < 0.01);
}

TEST_CASE("A catch point beyond reach is judged so only after the verdict delay") {
  const Throw t;
  const CatchSettings s;
  CatchCoordinator c(s, {});
  AttemptReport r = waiting(t, s.reach_m + 0.2);
  c.plan(r, t.launch_s, t.optimal.t_s);
  r.launch_s = t.launch_s;
  c.update(t.launch_s + 0.05, view(t, Task::wait, 0.05), r);
  CHECK_FALSE(c.unreachable());
  c.update(t.launch_s + s.verdict_delay_s + 0.001, view(t, Task::wait, s.verdict_delay_s), r);
  CHECK(c.unreachable());
  c.reset();
  CHECK_FALSE(c.unreachable());
}

TEST_CASE("A manoeuvre beyond the catcher's inputs is infeasible") {
  const Throw t;
  const CatchSettings s;
  CatchCoordinator c(s, gs::planning::InputLimits{1.0, 20.0, 0.05});  // hardly any body rate
  AttemptReport r = waiting(t, 0.5);
  c.plan(r, t.launch_s, t.optimal.t_s);
  r.launch_s = t.launch_s;
  c.update(t.launch_s + s.verdict_delay_s + 0.001, view(t, Task::wait, s.verdict_delay_s), r);
  CHECK_FALSE(c.unreachable());
  CHECK(c.infeasible());
}

TEST_CASE("Nothing is judged for a catcher that is neither waiting nor catching") {
  const Throw t;
  CatchCoordinator c(CatchSettings{}, {});
  AttemptReport r = waiting(t, 5.0);
  c.plan(r, t.launch_s, t.optimal.t_s);
  r.launch_s = t.launch_s;
  c.update(t.launch_s + 0.5, view(t, Task::clear, 0.5), r);
  CHECK_FALSE(r.predicted);
  CHECK_FALSE(c.unreachable());
}

TEST_CASE("The retiming moves the catch's end height to this flight's (42), within its bounds") {
  const Throw t;
  CatchSettings s;
  s.retime_max_m = 0.1;
  s.min_height_m = 0.0;  // the Fig. 5 throw's heights, from its origin: no floor in the way
  CatchCoordinator c(s, {});
  AttemptReport r = waiting(t, 0.0);
  r.catch_height_m += 0.3;  // the adapted height 0.3 m above this flight's
  const double adapted = r.catch_height_m;
  c.plan(r, t.launch_s, t.optimal.t_s);
  r.launch_s = t.launch_s;
  const double planned = c.start_s();
  const double end_s = planned + c.z_manoeuvre(adapted).duration_s();
  // Until the prediction has settled the (42) is noted, the height not yet moved.
  c.retime(t.launch_s + 0.5 * s.verdict_delay_s, view(t, Task::catching, 0.0), r);
  REQUIRE(r.predicted_optimal);
  CHECK(r.predicted_optimal->height_m == Approx(t.optimal.catch_height_m).margin(0.01));
  CHECK(r.catch_height_m == adapted);
  CHECK(c.height_shift().target_m() == 0.0);
  const double now = t.launch_s + s.verdict_delay_s + 0.01;
  c.retime(now, view(t, Task::catching, 0.0), r);
  CHECK(r.catch_height_m == Approx(adapted - s.retime_max_m));
  CHECK(c.height_shift().target_m() == Approx(-s.retime_max_m));
  // The end keeps its time; the shift starts from rest where it was and ends at rest at the end.
  CHECK(c.start_s() == planned);
  CHECK(c.height_shift().at(now).z_m == Approx(0.0).margin(1e-12));
  CHECK(c.height_shift().at(now).dz_mps == Approx(0.0).margin(1e-12));
  CHECK(c.height_shift().at(end_s).z_m == Approx(-s.retime_max_m));
  CHECK(c.height_shift().at(end_s - 1e-6).dz_mps == Approx(0.0).margin(1e-4));
  // The trajectory flown is the adapted one: the shift carries the difference.
  c.update(now, view(t, Task::catching, 0.0), r);
  REQUIRE(c.trajectory());
  CHECK(c.trajectory()->params().catch_height_m == Approx(adapted - pa::kPlateHeightAboveCg_m));
  // After retime_s it holds.
  const double height = r.catch_height_m;
  c.retime(t.launch_s + s.retime_s + 0.01, view(t, Task::catching, 0.0), r);
  CHECK(r.catch_height_m == height);
}

TEST_CASE("Upwards the retiming reaches farther than downwards") {
  const Throw t;
  CatchSettings s;
  s.retime_max_m = 0.1;
  s.retime_up_max_m = 0.2;
  s.min_height_m = 0.0;
  CatchCoordinator c(s, {});
  AttemptReport r = waiting(t, 0.0);
  r.catch_height_m -= 0.3;  // the adapted height 0.3 m below this flight's (42)
  const double adapted = r.catch_height_m;
  c.plan(r, t.launch_s, t.optimal.t_s);
  r.launch_s = t.launch_s;
  c.retime(t.launch_s + s.verdict_delay_s + 0.01, view(t, Task::catching, 0.0), r);
  CHECK(r.catch_height_m == Approx(adapted + s.retime_up_max_m));
  CHECK(c.height_shift().target_m() == Approx(s.retime_up_max_m));
}

TEST_CASE("No catch is planned below the floor, however low this flight's (42) lies") {
  const Throw t;
  CatchSettings s;
  s.min_height_m = t.optimal.catch_height_m + 0.2;  // (42) lies below the floor
  CHECK(gs::runtime::floored_catch_height_m(s.min_height_m - 1.0, s) == s.min_height_m);
  CHECK(gs::runtime::floored_catch_height_m(s.min_height_m + 1.0, s) == s.min_height_m + 1.0);
  CatchCoordinator c(s, {});
  AttemptReport r = waiting(t, 0.0);
  r.catch_height_m = s.min_height_m + 0.1;
  c.plan(r, t.launch_s, t.optimal.t_s);
  r.launch_s = t.launch_s;
  c.retime(t.launch_s + 0.2, view(t, Task::catching, 0.0), r);
  CHECK(r.catch_height_m == Approx(s.min_height_m));  // down to (42) by the bound, held at the floor
}

TEST_CASE("For a pole later than the learnt instant the shift ends at rest when it arrives") {
  const Throw t;
  CatchSettings s;
  s.min_height_m = 0.0;
  const double arrival_s = t.launch_s + t.optimal.t_s;
  for (const double learnt_early_s : {0.2, -0.1}) {
    CAPTURE(learnt_early_s);
    CatchCoordinator c(s, {});
    AttemptReport r = waiting(t, 0.0);
    r.catch_height_m += 0.6;  // the adapted height above this flight's (42)
    const double adapted = r.catch_height_m;
    c.plan(r, t.launch_s, t.optimal.t_s - learnt_early_s);
    r.launch_s = t.launch_s;
    const double manoeuvre_end_s = c.start_s() + c.z_manoeuvre(adapted).duration_s();
    const double end_s = std::max(manoeuvre_end_s, arrival_s);
    c.retime(t.launch_s + s.verdict_delay_s + 0.01, view(t, Task::catching, 0.0), r);
    CHECK(r.catch_height_m == Approx(t.optimal.catch_height_m).margin(0.01));
    const double target = c.height_shift().target_m();
    CHECK(c.height_shift().at(end_s).z_m == Approx(target));
    CHECK(c.height_shift().at(end_s - 1e-6).dz_mps == Approx(0.0).margin(1e-4));
    // Still on its way at the manoeuvre's end when the pole comes later than learnt.
    if (arrival_s > manoeuvre_end_s) CHECK(c.height_shift().at(manoeuvre_end_s).z_m > target + 0.01);
  }
}
