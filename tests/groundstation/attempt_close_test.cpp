// The end of an attempt (groundstation/runtime/attempt_close.hpp): the launch flown against the
// plan, the record and what the learner takes of a Fig. 5 throw and of a throw to a target.
#include <catch2/catch.hpp>

#include "groundstation/planning/throw_book.hpp"
#include "groundstation/runtime/attempt_close.hpp"

namespace {

using gs::adaptation::Learner;
using gs::adaptation::ThrowOutcome;
using namespace gs::runtime;

const gs::model::VehicleLimits kLimits{1.0, 20.0, 10.0};

const gs::planning::ThrowBook& book() {
  static const gs::planning::ThrowBook b(kLimits, {});
  return b;
}

Learner learner() {
  gs::adaptation::AdaptationSettings s;
  s.nominal_catch_height_m = -0.6;
  s.nominal_waiting_xy_m = Eigen::Vector2d(3.5, 0.0);
  s.target_energy_J = 0.196;
  gs::adaptation::LearnerSettings settings;
  settings.throw_learning.gain = 0.5;  // the launch is learnt
  const gs::planning::ThrowTrajectory& plan = book().plan().trajectory;
  return Learner(settings, s, 0.8, gs::planning::launch_state_of(plan.state_at(plan.duration_s())),
                 gs::adaptation::LaunchMatrix::Identity(), std::nullopt, "");
}

// A Fig. 5 throw from vehicle 1's frame, launched at 11 s, its last tracked state `off` from the
// plan 5 ms before T.
struct Closing {
  AttemptRequest request;
  AttemptReport report;
  AttemptFlight flight;
  std::vector<gs::adaptation::TimedPoleState> pole_flight;
};
Closing launched(double off_x_m) {
  Closing c;
  c.report.number = 1;
  c.report.throw_start_s = 10.0;
  c.report.launch_s = 11.0;
  c.report.catch_height_m = 1.4;
  c.flight.plan = &book().plan().trajectory;
  c.flight.frame = gs::control::ThrowFrame{Eigen::Vector3d(0.0, 0.0, 2.0), 0.0};
  const double tau = c.flight.plan->duration_s() - 0.005;
  gs::model::PlanarState<double> state = c.flight.plan->state_at(tau);
  state(0) += off_x_m;
  c.flight.throw_end = gs::runtime::ThrowEnd{tau, state};
  return c;
}

}  // namespace

TEST_CASE("The launch flown is the last tracked state carried to T; a Fig. 5 throw's is learnt") {
  Learner l = learner();
  Closing c = launched(0.0);
  c.flight.pole_flight = &c.pole_flight;
  close_attempt(c.request, c.report, c.flight, 12.0, l);
  REQUIRE(c.report.launch_flown);
  REQUIRE(c.report.launch_error);
  CHECK(c.report.launch_error->norm() == Approx(0.0).margin(1e-9));
  CHECK_FALSE(c.report.optimal);  // fewer than two poses of its flight: nothing to evaluate
  REQUIRE(l.records().size() == 1);
  CHECK(l.records()[0].time_s == 11.0);  // the launch's time
  CHECK(l.records()[0].note.empty());

  Learner off = learner();
  Closing c2 = launched(0.02);
  c2.flight.pole_flight = &c2.pole_flight;
  close_attempt(c2.request, c2.report, c2.flight, 12.0, off);
  CHECK(c2.report.launch_error->norm() == Approx(0.02));
  CHECK(off.throw_correction(pa::kVehicle1).end_shift.norm() > 0.0);  // learnt from
  CHECK(l.throw_correction(pa::kVehicle1).end_shift.norm() == Approx(0.0).margin(1e-12));
}

TEST_CASE("A throw to a target is kept, noted, and teaches neither the launch nor the adaptation") {
  Learner l = learner();
  const gs::adaptation::AdaptationState before = l.state();
  Closing c = launched(0.02);
  c.flight.pole_flight = &c.pole_flight;
  gs::planning::ThrowBook planner(kLimits, {});
  const std::optional<gs::planning::TargetThrow> target = planner.plan_to(
      Eigen::Vector3d(0.0, 0.0, 2.0), Eigen::Vector3d(0.0, 3.5, 1.3), Eigen::Vector3d::Zero());
  REQUIRE(target);
  c.flight.target_throw = &*target;
  close_attempt(c.request, c.report, c.flight, 12.0, l);
  REQUIRE(l.records().size() == 1);
  CHECK(l.records()[0].note == "a throw to a target: not adapted");
  CHECK(l.throw_correction(pa::kVehicle1).end_shift.norm() == Approx(0.0).margin(1e-12));
  CHECK(l.state().catch_height_m == before.catch_height_m);
  CHECK(l.target_miss_m().isZero());  // no agreed evaluation: no miss learnt
}

TEST_CASE("An attempt that never launched is recorded at its end, without a launch") {
  Learner l = learner();
  Closing c = launched(0.0);
  c.report.launch_s.reset();
  c.flight.pole_flight = &c.pole_flight;
  c.request.catch_it = false;
  close_attempt(c.request, c.report, c.flight, 12.5, l);
  CHECK_FALSE(c.report.launch_flown);
  CHECK_FALSE(c.report.optimal);
  REQUIRE(l.records().size() == 1);
  CHECK(l.records()[0].time_s == 12.5);
  CHECK(l.records()[0].outcome == ThrowOutcome::throw_only);
}

TEST_CASE("The free flight is recorded from the launch to the impact, free-flight estimates in time order") {
  std::vector<gs::adaptation::TimedPoleState> flight;
  AttemptReport report;
  gs::estimation::PoleEstimate pole;
  pole.valid = true;
  pole.mode = gs::estimation::PoleMode::free;
  pole.t_s = 1.0;
  record_free_flight(flight, pole, report);
  CHECK(flight.empty());  // not launched
  report.launch_s = 0.9;
  record_free_flight(flight, pole, report);
  REQUIRE(flight.size() == 1);
  record_free_flight(flight, pole, report);  // the same estimate again
  CHECK(flight.size() == 1);
  pole.t_s = 1.005;
  pole.mode = gs::estimation::PoleMode::on_vehicle1;
  record_free_flight(flight, pole, report);
  CHECK(flight.size() == 1);  // not free
  pole.mode = gs::estimation::PoleMode::free;
  pole.valid = false;
  record_free_flight(flight, pole, report);
  CHECK(flight.size() == 1);  // not seen
  pole.valid = true;
  record_free_flight(flight, pole, report);
  CHECK(flight.size() == 2);
  CHECK(flight.back().t_s == 1.005);
  report.impact_s = 1.01;
  pole.t_s = 1.02;
  record_free_flight(flight, pole, report);
  CHECK(flight.size() == 2);  // after the impact
}
