// The facts of a vehicle's condition word (groundstation/runtime/condition_facts.hpp): the link's
// view, the vehicle's own clocks and requests, and the attempt's part, each from where the
// runtime keeps it. (An estimator that has seen nothing: no estimate, no pole.)
#include <catch2/catch.hpp>

#include <cmath>

#include "groundstation/runtime/condition_facts.hpp"

namespace {

using gs::mission::ConditionFacts;
using gs::mission::Task;
using gs::runtime::AttemptPhase;
using gs::runtime::AttemptView;
using gs::runtime::VehicleView;

gs::link::VehicleLinkStatus heard(pa::proto::Mode mode) {
  gs::link::VehicleLinkStatus s;
  s.vehicle = pa::kVehicle2;
  s.heard = true;
  s.lost = false;
  s.mode = mode;
  s.armed = mode == pa::proto::Mode::armed;
  s.flags = pa::proto::kFlagGroundHeartbeatOk;
  return s;
}

VehicleView catcher() {
  VehicleView v;
  v.id = pa::kVehicle2;
  v.requests = gs::mission::condition::request_catch;
  v.task = Task::wait;
  v.task_since_s = 4.0;
  v.last_pose_s = 9.995;
  v.target_m = Eigen::Vector3d(3.5, 0.0, 1.7);
  return v;
}

ConditionFacts facts(const VehicleView& v, const gs::link::VehicleLinkStatus& link,
                     const AttemptView& attempt) {
  static const gs::estimation::StateEstimator estimator;
  return gs::runtime::condition_facts(v, link, estimator, attempt, 10.0);
}

}  // namespace

TEST_CASE("The vehicle's own facts: requests, command, task clock, pose age, target") {
  VehicleView v = catcher();
  v.command_failed = true;
  const ConditionFacts f = facts(v, heard(pa::proto::Mode::armed), {});
  CHECK(f.requests == v.requests);
  CHECK(f.command_failed);
  CHECK(f.task == Task::wait);
  CHECK(f.in_task_s == 6.0);
  CHECK(f.since_pose_s == Approx(0.005));
  CHECK(f.target_m == v.target_m);
  CHECK_FALSE(f.estimated);  // the estimator has no estimate of it yet
  CHECK_FALSE(f.pole_end_from_plate_m);
}

TEST_CASE("The link: up only both ways, armed as reported, on the ground disarmed, landed or killed") {
  CHECK(facts(catcher(), heard(pa::proto::Mode::armed), {}).link_up);
  CHECK(facts(catcher(), heard(pa::proto::Mode::armed), {}).armed);
  gs::link::VehicleLinkStatus deaf = heard(pa::proto::Mode::armed);
  deaf.flags = 0;  // it does not hear our heartbeats
  CHECK_FALSE(facts(catcher(), deaf, {}).link_up);
  gs::link::VehicleLinkStatus lost = heard(pa::proto::Mode::armed);
  lost.lost = true;
  CHECK_FALSE(facts(catcher(), lost, {}).link_up);
  for (pa::proto::Mode m : {pa::proto::Mode::disarmed, pa::proto::Mode::landed, pa::proto::Mode::killed})
    CHECK(facts(catcher(), heard(m), {}).on_ground);
  CHECK_FALSE(facts(catcher(), heard(pa::proto::Mode::armed), {}).on_ground);
}

TEST_CASE("The attempt's facts reach the catcher only, while an attempt runs") {
  AttemptView a;
  a.phase = AttemptPhase::throwing;
  a.catch_it = true;
  a.throw_duration_s = 1.1;
  a.catch_due = a.catch_unreachable = a.catch_infeasible = a.catch_missed = true;
  ConditionFacts f = facts(catcher(), heard(pa::proto::Mode::armed), a);
  CHECK(f.catcher);
  CHECK(f.catch_due);
  CHECK(f.throw_duration_s == 1.1);
  VehicleView thrower = catcher();
  thrower.id = pa::kVehicle1;
  CHECK_FALSE(facts(thrower, heard(pa::proto::Mode::armed), a).catcher);
  a.catch_it = false;
  CHECK_FALSE(facts(catcher(), heard(pa::proto::Mode::armed), a).catcher);
  a.catch_it = true;
  a.phase = AttemptPhase::idle;
  CHECK_FALSE(facts(catcher(), heard(pa::proto::Mode::armed), a).catcher);
  // The catch is due only while the throw or the flight runs.
  for (AttemptPhase p : {AttemptPhase::idle, AttemptPhase::preparing, AttemptPhase::balancing}) {
    a.phase = p;
    CHECK_FALSE(facts(catcher(), heard(pa::proto::Mode::armed), a).catch_due);
  }
  a.phase = AttemptPhase::flight;
  CHECK(facts(catcher(), heard(pa::proto::Mode::armed), a).catch_due);
}

TEST_CASE("The pole on the floor counts only in an attempt's flight, below pole_down_height_m") {
  AttemptView a;
  a.pole_seen_height_m = a.pole_down_height_m - 0.01;
  for (AttemptPhase p : {AttemptPhase::idle, AttemptPhase::preparing, AttemptPhase::throwing}) {
    a.phase = p;
    CHECK_FALSE(facts(catcher(), heard(pa::proto::Mode::armed), a).pole_on_floor);
  }
  for (AttemptPhase p : {AttemptPhase::flight, AttemptPhase::balancing}) {
    a.phase = p;
    CHECK(facts(catcher(), heard(pa::proto::Mode::armed), a).pole_on_floor);
  }
  a.pole_seen_height_m = a.pole_down_height_m;
  CHECK_FALSE(facts(catcher(), heard(pa::proto::Mode::armed), a).pole_on_floor);
  a.pole_seen_height_m.reset();
  CHECK_FALSE(facts(catcher(), heard(pa::proto::Mode::armed), a).pole_on_floor);
}

TEST_CASE("A pass's thrower preparing is at its origin within the pass's distance; no one else") {
  AttemptView a;
  a.phase = AttemptPhase::preparing;
  a.thrower = pa::kVehicle2;
  CHECK_FALSE(facts(catcher(), heard(pa::proto::Mode::armed), a).at_target_within_m);  // not a pass
  a.thrower_at_origin_m = 0.15;
  REQUIRE(facts(catcher(), heard(pa::proto::Mode::armed), a).at_target_within_m);
  CHECK(*facts(catcher(), heard(pa::proto::Mode::armed), a).at_target_within_m == 0.15);
  a.thrower = pa::kVehicle1;  // the other vehicle's target keeps the thresholds' distance
  CHECK_FALSE(facts(catcher(), heard(pa::proto::Mode::armed), a).at_target_within_m);
  a.thrower = pa::kVehicle2;
  for (AttemptPhase p : {AttemptPhase::idle, AttemptPhase::throwing, AttemptPhase::flight}) {
    a.phase = p;
    CHECK_FALSE(facts(catcher(), heard(pa::proto::Mode::armed), a).at_target_within_m);
  }
}

TEST_CASE("Balanced for: since the pole settled") {
  AttemptView a;
  CHECK_FALSE(facts(catcher(), heard(pa::proto::Mode::armed), a).balanced_for_s);
  a.balanced_since_s = 8.5;
  CHECK(*facts(catcher(), heard(pa::proto::Mode::armed), a).balanced_for_s == 1.5);
}

TEST_CASE("The pole's end nearest the plate, either end") {
  gs::estimation::MocapPose pose;
  pose.p_m = Eigen::Vector3d(0.0, 0.0, 2.0);
  const Eigen::Vector3d plate(0.0, 0.0, 1.7);
  CHECK(gs::runtime::pole_end_from_plate_m(pose, plate, 0.26) == Approx(0.04));
  pose.q = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()));  // upside down
  CHECK(gs::runtime::pole_end_from_plate_m(pose, plate, 0.26) == Approx(0.04));
  pose.q = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()));  // lying
  CHECK(gs::runtime::pole_end_from_plate_m(pose, plate, 0.26) == Approx(std::hypot(0.26, 0.3)));
}
