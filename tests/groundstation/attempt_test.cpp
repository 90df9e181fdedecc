// The attempt's account (groundstation/runtime/attempt.hpp): how an attempt's end is classed for
// the adaptation, and its record in the throw's own frame.
#include <catch2/catch.hpp>

#include "groundstation/runtime/attempt.hpp"

namespace {

using gs::adaptation::ThrowOutcome;
using gs::mission::Reason;
using gs::runtime::AttemptReport;
using gs::runtime::AttemptRequest;
using gs::runtime::outcome_of;
using gs::runtime::record_of;

}  // namespace

TEST_CASE("An attempt's end is classed by what ended the catch, in order of precedence") {
  AttemptRequest request;
  AttemptReport report;
  CHECK(outcome_of(request, report) == ThrowOutcome::missed);
  report.impact_s = 12.0;
  CHECK(outcome_of(request, report) == ThrowOutcome::dropped);
  request.catch_offset_m = Eigen::Vector2d(1.0, 0.0);
  CHECK(outcome_of(request, report) == ThrowOutcome::offset_practice);
  for (Reason r :
       {Reason::infeasible, Reason::abort_requested, Reason::vehicle_lost, Reason::estimate_lost}) {
    report.catcher_end = r;
    CHECK(outcome_of(request, report) == ThrowOutcome::aborted);
  }
  report.catcher_end = Reason::out_of_reach;
  CHECK(outcome_of(request, report) == ThrowOutcome::aborted_out_of_reach);
  report.caught = true;  // balanced on the catcher outranks whatever ended the catch manoeuvre
  CHECK(outcome_of(request, report) == ThrowOutcome::caught);
  request.catch_it = false;
  CHECK(outcome_of(request, report) == ThrowOutcome::throw_only);
}

TEST_CASE("The record is the throw's, in its frame") {
  // Vehicle 2's frame: from (3.5, 0) back towards -x, the origin 2 m up.
  const gs::control::ThrowFrame frame{Eigen::Vector3d(3.5, 0.0, 2.0), M_PI};
  AttemptRequest request;
  AttemptReport report;
  report.catch_height_m = 1.4;
  report.waiting_xy_m = Eigen::Vector2d(0.2, 0.1);
  const Eigen::Vector2d target(0.1, -0.1);
  gs::adaptation::ThrowRecord r = record_of(request, report, frame, target, 30.0);
  CHECK(r.time_s == 30.0);  // never launched: the attempt's end
  CHECK(r.catch_height_used_m == Approx(-0.6));
  CHECK(r.waiting_xy_m.isApprox(Eigen::Vector2d(3.3, -0.1)));
  CHECK_FALSE(r.target_xy_m);  // no catch manoeuvre started
  CHECK_FALSE(r.catcher_at_impact_xy_m);
  report.launch_s = 21.0;
  report.catch_start_s = 20.5;
  report.impact_s = 22.0;
  report.caught = true;
  report.catcher_at_impact_m = Eigen::Vector3d(0.0, 0.0, 1.5);
  report.launch_flown = gs::planning::PlanarLaunchState{1.5, 2.0, 0.3, 5.5, 0.48, 2.5};
  r = record_of(request, report, frame, target, 30.0);
  CHECK(r.time_s == 21.0);
  CHECK(r.outcome == ThrowOutcome::caught);
  CHECK(r.launch.vz_mps == 5.5);
  REQUIRE(r.target_xy_m);
  CHECK(r.target_xy_m->isApprox(Eigen::Vector2d(3.4, 0.1)));
  REQUIRE(r.catcher_at_impact_xy_m);
  CHECK(r.catcher_at_impact_xy_m->isApprox(Eigen::Vector2d(3.5, 0.0)));
  // A catch aborted for reach: the catcher never flew to its target, its place says nothing.
  report.caught = false;
  report.catcher_end = Reason::out_of_reach;
  CHECK_FALSE(record_of(request, report, frame, target, 30.0).catcher_at_impact_xy_m);
}

TEST_CASE("A task entered tells the report the impact and what ended the throw and the catch, once") {
  using gs::mission::Task;
  AttemptRequest request;  // vehicle 1 throws, vehicle 2 catches
  AttemptReport report;
  const Eigen::Vector3d here(3.4, 0.1, 1.5);
  gs::runtime::note_task_entry(request, true, report, pa::kVehicle2, Task::rebalance, Reason::caught, 12.0,
                               here);
  CHECK(report.impact_s == 12.0);
  CHECK(report.catcher_at_impact_m == here);
  CHECK(report.catcher_end == Reason::caught);
  gs::runtime::note_task_entry(request, true, report, pa::kVehicle2, Task::rebalance, Reason::caught, 13.0,
                               Eigen::Vector3d::Zero());
  CHECK(report.impact_s == 12.0);  // the first impact
  gs::runtime::note_task_entry(request, true, report, pa::kVehicle2, Task::clear, Reason::pole_lost, 14.0,
                               here);
  CHECK(report.catcher_end == Reason::caught);  // noted once

  AttemptReport throw_report;
  gs::runtime::note_task_entry(request, false, throw_report, pa::kVehicle1, Task::release,
                               Reason::throw_ended, 11.0, here);
  CHECK(throw_report.thrower_end == Reason::none);  // no attempt running
  gs::runtime::note_task_entry(request, true, throw_report, pa::kVehicle2, Task::release, Reason::throw_ended,
                               11.0, here);
  CHECK(throw_report.thrower_end == Reason::none);  // not the thrower
  gs::runtime::note_task_entry(request, true, throw_report, pa::kVehicle1, Task::release,
                               Reason::pole_left_early, 11.0, here);
  CHECK(throw_report.thrower_end == Reason::pole_left_early);
  // A catcher hovering again ends its catch only once the catch had started.
  gs::runtime::note_task_entry(request, true, throw_report, pa::kVehicle2, Task::hover,
                               Reason::abort_requested, 11.5, here);
  CHECK(throw_report.catcher_end == Reason::none);
  throw_report.catch_start_s = 11.2;
  gs::runtime::note_task_entry(request, true, throw_report, pa::kVehicle2, Task::hover, Reason::pole_down,
                               11.5, here);
  CHECK(throw_report.catcher_end == Reason::pole_down);
  // Without a catch, no catcher's end.
  request.catch_it = false;
  AttemptReport alone;
  gs::runtime::note_task_entry(request, true, alone, pa::kVehicle2, Task::clear, Reason::out_of_reach, 11.5,
                               here);
  CHECK(alone.catcher_end == Reason::none);
}
