// The attempt the runtime flies (groundstation/runtime/attempt_runner.hpp), with no flight behind
// it: the vehicles' sequencers are stepped by hand through the mission table, so each test sets
// up the tasks an attempt meets. Admission and where it sends each vehicle, the throw asked for
// once both are in place, the throw's start noted and the catch planned from it, an attempt that
// ends before the launch, and what the task laws are handed to fly.
#include <catch2/catch.hpp>

#include <initializer_list>

#include "groundstation/runtime/attempt_runner.hpp"
#include "groundstation/runtime/throw_geometry.hpp"

namespace {

using gs::mission::Reason;
using gs::mission::Task;
using namespace gs::runtime;
namespace c = gs::mission::condition;

gs::adaptation::Learner learner_for(const GroundStationConfig& config,
                                    const gs::planning::ThrowBook& throws) {
  const gs::planning::ThrowTrajectory& plan = throws.plan().trajectory;
  return gs::adaptation::Learner(
      config.learning, gs::adaptation::nominal_adaptation_settings(config.estimator.free_flight.pole), 0.8,
      gs::planning::launch_state_of(plan.state_at(plan.duration_s())),
      gs::adaptation::LaunchMatrix::Identity(), std::nullopt, "");
}

struct Rig {
  GroundStationConfig config;
  gs::estimation::StateEstimator estimator{config.estimator};
  gs::planning::ThrowBook throws{config.limits, config.throw_tracking};
  gs::adaptation::Learner learner = learner_for(config, throws);
  gs::adaptation::IdentificationMemory identifications{
      {}, "", gs::adaptation::nominal_adaptation_settings(config.estimator.free_flight.pole)};
  AttemptRunner runner{config, estimator, learner, throws, identifications};
  ActVehicles vehicles{ActVehicle(pa::kVehicle1, {}), ActVehicle(pa::kVehicle2, {})};
  int thrust_asked = 0;
  double gain = 1.0;  // both vehicles' thrust gain, as thrust_of reports it

  bool request(const AttemptRequest& request) {
    return runner.request(request, vehicles, [this](pa::VehicleId v) {
      ++thrust_asked;
      return VehicleThrust{v, gain, 0.0};
    });
  }
  ActVehicle& thrower() { return vehicles[0]; }
  ActVehicle& catcher() { return vehicles[1]; }
};

// Steps a sequencer through the mission table, one condition word a step (each with `armed`).
void step(ActVehicle& v, std::initializer_list<std::uint32_t> words, double& t_s) {
  for (const std::uint32_t word : words) {
    v.sequencer.step(word | c::armed, t_s);
    t_s += 0.005;
  }
}
// Flies `v`'s identification flight, hovering at its target, until its fit is in; no telemetry
// comes back, so it is refused (no_telemetry).
void fly_refused_identification(ActVehicle& v, gs::adaptation::IdentificationMemory& memory, double& t_s) {
  for (int i = 0; i < 1000 && v.adaptation.motors().flight().running(); ++i) {
    v.adaptation.identify(t_s, Task::hover, true, memory);
    t_s += 0.005;
  }
}
// parked -> arming -> take_off -> hover.
void take_off(ActVehicle& v, double& t_s) {
  v.sequencer.step(c::request_take_off, t_s);
  step(v, {0, c::at_height}, t_s);
  REQUIRE(v.sequencer.task() == Task::hover);
}

}  // namespace

TEST_CASE(
    "An attempt is admitted once at a time: the thrower to its throw's origin, the catcher asked to catch") {
  Rig rig;
  REQUIRE(rig.request(AttemptRequest{}));
  CHECK(rig.runner.phase() == AttemptPhase::preparing);
  CHECK(rig.runner.current().number == 1);
  CHECK(rig.thrower().laws.target_m == throw_start_m(rig.runner.throw_frame(pa::kVehicle1)));
  CHECK(rig.catcher().requests == c::request_catch);
  CHECK(rig.thrower().requests == 0);

  CHECK_FALSE(rig.request(AttemptRequest{}));
  CHECK(rig.runner.refusal_kind() == AttemptRefusal::busy);
  CHECK(rig.runner.current().number == 1);

  // Not of the act: refused before anything is asked of the vehicles.
  Rig other;
  AttemptRequest stranger;
  stranger.thrower = pa::VehicleId(5);
  CHECK_FALSE(other.request(stranger));
  CHECK(other.runner.refusal_kind() == AttemptRefusal::not_of_act);
  CHECK(other.thrust_asked == 0);
  // Too weak: refused, and neither vehicle is sent anywhere.
  other.gain = 0.5;
  const Eigen::Vector3d before = other.thrower().laws.target_m;
  CHECK_FALSE(other.request(AttemptRequest{}));
  CHECK(other.runner.refusal_kind() == AttemptRefusal::too_weak);
  CHECK(other.runner.phase() == AttemptPhase::idle);
  CHECK(other.thrower().laws.target_m == before);
  CHECK(other.catcher().requests == 0);
  // Strong enough again: admitted, the refusal cleared.
  other.gain = 1.0;
  CHECK(other.request(AttemptRequest{}));
  CHECK(other.runner.refusal().empty());
}

TEST_CASE("The throw is asked for once the thrower is at its origin and the catcher waits at its point") {
  Rig rig;
  double t = 10.0;
  take_off(rig.thrower(), t);
  take_off(rig.catcher(), t);
  REQUIRE(rig.request(AttemptRequest{}));
  step(rig.catcher(), {c::request_catch}, t);
  REQUIRE(rig.catcher().sequencer.task() == Task::wait);

  step(rig.thrower(), {c::at_target}, t);  // at its origin; the catcher still on its way
  rig.runner.update(t, rig.vehicles);
  CHECK((rig.thrower().requests & c::request_throw) == 0);
  step(rig.catcher(), {c::request_catch | c::at_target}, t);
  rig.runner.update(t, rig.vehicles);
  CHECK((rig.thrower().requests & c::request_throw) != 0);
  CHECK(rig.runner.phase() == AttemptPhase::preparing);

  // The thrower balances and throws: the attempt notes the throw's start and plans the catch.
  step(rig.thrower(), {c::pole_on_self | c::pole_upright, c::pole_on_self | c::request_throw | c::settled},
       t);
  REQUIRE(rig.thrower().sequencer.task() == Task::throwing);
  const double thrown_s = rig.thrower().sequencer.task_since_s();
  rig.runner.update(t, rig.vehicles);
  CHECK(rig.runner.phase() == AttemptPhase::throwing);
  CHECK(rig.runner.current().throw_start_s == thrown_s);
  CHECK(rig.runner.current().catch_height_m == rig.runner.catch_height());
  CHECK(rig.runner.view(t).phase == AttemptPhase::throwing);

  // The catcher's catch starts: its window runs from now.
  TaskEntryContext context;
  rig.runner.entering(Task::catching, t, context);
  CHECK(rig.runner.current().catch_start_s == t);
  CHECK(context.catch_window_s > 0.0);

  // The thrower retreats without the estimator ever calling a launch: the throw is abandoned.
  step(rig.thrower(), {c::throw_over}, t);
  REQUIRE(rig.thrower().sequencer.task() == Task::release);
  rig.runner.update(t, rig.vehicles);
  CHECK(rig.runner.phase() == AttemptPhase::throwing);  // releasing: not yet
  step(rig.thrower(), {c::release_over}, t);
  REQUIRE(rig.thrower().sequencer.task() == Task::retreat);
  rig.runner.update(t, rig.vehicles);
  CHECK(rig.runner.phase() == AttemptPhase::idle);
  REQUIRE(rig.runner.reports().size() == 1);
  CHECK_FALSE(rig.runner.reports()[0].caught);
  CHECK((rig.thrower().requests & c::request_throw) == 0);
  CHECK((rig.catcher().requests & c::request_catch) == 0);
}

TEST_CASE("A catcher lost before the throw ends the attempt; both vehicles are sent back to their points") {
  Rig rig;
  double t = 10.0;
  take_off(rig.catcher(), t);
  REQUIRE(rig.request(AttemptRequest{}));
  rig.runner.update(t, rig.vehicles);
  REQUIRE(rig.runner.phase() == AttemptPhase::preparing);
  step(rig.catcher(), {c::vehicle_lost}, t);
  REQUIRE(rig.catcher().sequencer.task() == Task::failsafe);
  rig.runner.update(t, rig.vehicles);
  CHECK(rig.runner.phase() == AttemptPhase::idle);
  REQUIRE(rig.runner.reports().size() == 1);
  CHECK(rig.runner.reports()[0].catcher_end == Reason::vehicle_lost);
  CHECK(rig.catcher().requests == 0);
  CHECK(rig.thrower().laws.target_m == throw_start_m(rig.runner.throw_frame(pa::kVehicle1)));
  CHECK(rig.catcher().laws.target_m == rig.runner.waiting_target());
}

TEST_CASE("A thrower whose motors could not be identified ends the attempt before the pole goes up") {
  Rig rig;
  double t = 10.0;
  take_off(rig.thrower(), t);
  REQUIRE(rig.request(AttemptRequest{}));
  rig.thrower().adaptation.start_identification(t);
  fly_refused_identification(rig.thrower(), rig.identifications, t);  // the take-off's flight
  REQUIRE(rig.thrower().adaptation.motors().identified());
  CHECK(rig.thrower().adaptation.motors().retry_due());
  rig.runner.update(t, rig.vehicles);
  CHECK(rig.runner.phase() == AttemptPhase::preparing);  // the retry is due: the pole waits
  rig.thrower().adaptation.identify(t, Task::hover, true, rig.identifications);  // starts it
  REQUIRE(rig.thrower().adaptation.motors().flight().running());
  fly_refused_identification(rig.thrower(), rig.identifications, t);
  REQUIRE(rig.thrower().adaptation.motors().refused());
  CHECK_FALSE(rig.runner.waiting_for_pole(rig.thrower()));  // not even until the next frame
  rig.runner.update(t, rig.vehicles);
  CHECK(rig.runner.phase() == AttemptPhase::idle);
  REQUIRE(rig.runner.reports().size() == 1);
  CHECK(rig.runner.reports()[0].end == AttemptEnd::motors_unidentified);
  CHECK(rig.catcher().requests == 0);
}

TEST_CASE(
    "The laws fly the Fig. 5 throw with the thrower's learnt correction, a throw to a target its own plan") {
  Rig rig;
  REQUIRE(rig.request(AttemptRequest{}));
  FlownThrow flown = rig.runner.flown();
  CHECK(flown.trajectory == &rig.throws.plan().trajectory);
  CHECK(flown.correction == &rig.learner.throw_correction(pa::kVehicle1));
  CHECK_FALSE(flown.catch_trajectory);  // no catch planned yet

  Rig aimed;
  AttemptRequest request;
  const Eigen::Vector3d origin = aimed.runner.throw_frame(pa::kVehicle1).origin_m;
  request.target_xy_m = Eigen::Vector2d(origin.x() + 3.0, origin.y() + 1.0);
  REQUIRE(aimed.request(request));
  flown = aimed.runner.flown();
  CHECK(flown.trajectory != &aimed.throws.plan().trajectory);
  CHECK(flown.correction == nullptr);
  CHECK(flown.frame.yaw_rad == Approx(std::atan2(1.0, 3.0)).margin(0.1));
  REQUIRE(aimed.runner.current().target_m);
  CHECK(aimed.runner.current().target_m->head<2>().isApprox(*request.target_xy_m, 1e-9));
  // The catcher waits above the target.
  CHECK((aimed.runner.waiting_target().head<2>() - *request.target_xy_m).norm() < 1e-9);
}
