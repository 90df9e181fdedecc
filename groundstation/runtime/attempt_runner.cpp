#include "groundstation/runtime/attempt_runner.hpp"

#include <algorithm>
#include <utility>

#include "groundstation/adaptation/throw_evaluation.hpp"
#include "groundstation/runtime/attempt_close.hpp"
#include "groundstation/runtime/throw_geometry.hpp"
#include "pa/constants.hpp"

namespace gs::runtime {
namespace {

namespace c = mission::condition;
using mission::Task;

planning::InputLimits input_limits(const model::VehicleLimits& l) {
  return {l.a_q_min_mps2, l.a_q_max_mps2, l.omega_max_radps};
}

ActVehicle& vehicle_of(ActVehicles& vehicles, pa::VehicleId id) { return vehicles[pa::act_slot(id)]; }
const ActVehicle& vehicle_of(const ActVehicles& vehicles, pa::VehicleId id) {
  return vehicles[pa::act_slot(id)];
}

}  // namespace

ThrustAdmission thrust_admission(const GroundStationConfig& config) {
  return {config.airframe_thrust_max_mps2, config.min_thrust_fraction, config.battery_reference_voltage_V,
          pa::kGravity_mps2 + config.catching.a_max_mps2, config.tasks.pole_weight_mps2 / pa::kGravity_mps2};
}

AttemptRunner::AttemptRunner(const GroundStationConfig& config, const estimation::StateEstimator& estimator,
                             adaptation::Learner& learner, planning::ThrowBook& throws,
                             const adaptation::IdentificationMemory& identifications)
    : config_(config),
      estimator_(estimator),
      learner_(learner),
      throws_(throws),
      identifications_(identifications),
      catch_(config.catching, input_limits(config.limits)) {
  frame_ = throw_frame(pa::kVehicle1);
}

control::ThrowFrame AttemptRunner::throw_frame(pa::VehicleId thrower) const {
  return throw_frame_of(thrower, config_.throw_origin_m, config_.throw_yaw_rad, adaptation());
}
std::optional<Eigen::Vector3d> AttemptRunner::aimed_m() const {
  return target_throw_ ? std::optional(target_throw_->plan.target_m) : std::nullopt;
}
Eigen::Vector2d AttemptRunner::waiting_xy() const { return catch_point_xy(frame_, adaptation(), aimed_m()); }
double AttemptRunner::catch_height() const {
  return floored_catch_height_m(
      catch_height_m(frame_, adaptation(), aimed_m(),
                     catch_energy_.height_offset_m(pa::other_vehicle(request_.thrower))),
      config_.catching);
}

// The pole's energy right after the impact on `catcher`'s plate (41), from its last free-flight
// estimate and the plate's velocity; the catcher's catching height learns from it
// (adaptation/catch_energy.hpp).
void AttemptRunner::measure_impact_energy(const ActVehicle& catcher) {
  if (flight_.empty()) return;
  const double energy_J = adaptation::post_impact_energy_J(
      flight_.back().state, estimator_.plate(catcher.id).v_mps, estimator_.pole_model());
  current_.energy_after_impact_J = energy_J;
  catch_energy_.learn(catcher.id, energy_J, learner_.adaptation_settings().target_energy_J);
}
Eigen::Vector3d AttemptRunner::waiting_target() const {
  const Eigen::Vector2d xy = waiting_xy() + request_.catch_offset_m;
  return Eigen::Vector3d(xy.x(), xy.y(), catch_.z_manoeuvre(catch_height()).start_height_m());
}
Eigen::Vector3d AttemptRunner::throw_origin_target() const { return throw_start_m(frame_); }
Eigen::Vector3d AttemptRunner::retreat_target() const {
  Eigen::Vector3d target = throw_origin_target();
  if (request_.thrower_catches_next) target.z() = std::max(target.z(), waiting_target().z());
  return target;
}
const planning::ThrowTrajectory& AttemptRunner::flown_throw() const {
  return target_throw_ ? target_throw_->plan.plan.trajectory : throws_.plan().trajectory;
}
const planning::ThrowTracker& AttemptRunner::flown_tracker() const {
  return target_throw_ ? target_throw_->tracker : throws_.tracker();
}
bool AttemptRunner::request(const AttemptRequest& request, ActVehicles& vehicles,
                            const std::function<VehicleThrust(pa::VehicleId)>& thrust_of) {
  const auto refuse = [&](Admission admission) {
    refusal_kind_ = admission.refusal;
    refusal_ = std::move(admission.why);
    return false;
  };
  if (Admission a = admit_request(phase_ != AttemptPhase::idle, request.thrower); !a.admitted())
    return refuse(std::move(a));
  const control::ThrowFrame frame = throw_frame(request.thrower);
  std::optional<planning::TargetThrow> target_throw;
  if (request.target_xy_m) {
    const Eigen::Vector3d target(request.target_xy_m->x(), request.target_xy_m->y(),
                                 frame.origin_m.z() + adaptation().catch_height_m);
    target_throw = throws_.plan_to(frame.origin_m, target, learner_.target_miss_m());
  }
  const planning::ThrowTrajectory* flown = !request.target_xy_m ? &throws_.plan().trajectory
                                           : target_throw       ? &target_throw->plan.plan.trajectory
                                                                : nullptr;
  // A target throw turns the frame to its own heading.
  const control::ThrowFrame flown_frame =
      target_throw ? control::ThrowFrame{frame.origin_m, target_throw->plan.yaw_rad} : frame;
  std::optional<VehicleThrust> catcher;
  if (request.catch_it) catcher = thrust_of(pa::other_vehicle(request.thrower));
  if (Admission a = admit_vehicles(flown, thrust_of(request.thrower), catcher, thrust_admission(config_));
      !a.admitted())
    return refuse(std::move(a));
  if (config_.arena_volume) {
    const std::optional<Eigen::Vector3d> aimed =
        target_throw ? std::optional<Eigen::Vector3d>(target_throw->target_m) : std::nullopt;
    const Eigen::Vector2d catch_xy = catch_point_xy(flown_frame, adaptation(), aimed);
    const Eigen::Vector3d catch_point(catch_xy.x(), catch_xy.y(),
                                      catch_height_m(flown_frame, adaptation(), aimed, 0.0));
    if (Admission a = admit_volume(planning::throw_reach(*flown, estimator_.pole_model()), flown_frame,
                                   catch_point, *config_.arena_volume);
        !a.admitted())
      return refuse(std::move(a));
  }
  refusal_kind_ = AttemptRefusal::none;
  refusal_.clear();
  target_throw_ = std::move(target_throw);
  frame_ = flown_frame;
  request_ = request;
  phase_ = AttemptPhase::preparing;
  current_ = AttemptReport{};
  current_.number = ++attempt_count_;
  current_.throw_correction = learner_.throw_correction(request.thrower).end_shift;
  throw_end_.reset();
  flight_.clear();
  catch_.reset();
  balanced_since_s_.reset();
  if (target_throw_) current_.target_m = target_throw_->target_m;
  ActVehicle& thrower = vehicle_of(vehicles, request.thrower);
  thrower.laws.target_m = throw_origin_target();
  if (request.catch_it) vehicle_of(vehicles, pa::other_vehicle(thrower.id)).requests |= c::request_catch;
  return true;
}

AttemptView AttemptRunner::view(double now_s) const {
  AttemptView attempt;
  attempt.phase = phase_;
  attempt.thrower = request_.thrower;
  attempt.catch_it = request_.catch_it;
  attempt.throw_duration_s = flown_throw().duration_s();
  attempt.catch_due = catch_.due(now_s);
  attempt.catch_unreachable = catch_.unreachable();
  attempt.catch_infeasible = catch_.infeasible();
  attempt.catch_missed = catch_.missed();
  attempt.balanced_since_s = balanced_since_s_;
  if (last_pole_pose_) attempt.pole_seen_height_m = last_pole_pose_->p_m.z();
  attempt.pole_pose = last_pole_pose_;
  attempt.pole_down_height_m = config_.attempt.pole_down_height_m;
  if (request_.thrower_catches_next) attempt.thrower_at_origin_m = config_.attempt.thrower_at_origin_m;
  return attempt;
}

void AttemptRunner::entering(Task task, double now_s, TaskEntryContext& context) {
  context.retreat_target_m = retreat_target();
  context.catch_target_xy_m = catch_.target_xy_m();
  if (task == Task::catching) {
    current_.catch_start_s = now_s;
    context.catch_window_s = catch_.start(now_s, catch_height(), config_.catch_window_margin_s);
  }
}

void AttemptRunner::entered(const ActVehicle& vehicle, bool estimated, double now_s,
                            const Eigen::Vector3d& here_m) {
  const Task task = vehicle.sequencer.task();
  if (task == Task::balance) balanced_since_s_.reset();
  // Where on the plate the pole rests as the throw starts (see the throwing task's control).
  if (task == Task::throwing)
    resting_offset_m_ = estimated && estimator_.pole().valid
                            ? resting_offset_m(estimator_.plate(vehicle.id), estimator_.pole().state,
                                               estimator_.pole_model().half_length_m)
                            : Eigen::Vector3d::Zero();
  if (task == Task::rebalance && !current_.impact_s) measure_impact_energy(vehicle);  // the first impact
  note_task_entry(request_, phase_ != AttemptPhase::idle, current_, vehicle.id, task,
                  vehicle.sequencer.last_reason(), now_s, here_m);
}

FlownThrow AttemptRunner::flown() const {
  FlownThrow flown{&flown_throw(),
                   &flown_tracker(),
                   frame_,
                   resting_offset_m_,
                   target_throw_ ? nullptr : &learner_.throw_correction(request_.thrower),
                   nullptr,
                   catch_.start_s()};
  if (catch_.trajectory()) flown.catch_trajectory = &*catch_.trajectory();
  flown.catch_height_shift = &catch_.height_shift();
  return flown;
}

void AttemptRunner::commanded(const TaskCommand& command, double now_s) {
  if (command.pole_settled) hold_since(balanced_since_s_, *command.pole_settled, now_s);
  if (command.throw_end) throw_end_ = command.throw_end;
}

CatchView AttemptRunner::catch_view(const ActVehicle& catcher) const {
  CatchView view;
  view.catcher_task = catcher.sequencer.task();
  view.pole = estimator_.pole();
  view.pole_model = estimator_.pole_model();
  view.catcher_position_m = estimator_.vehicle(catcher.id).state.p_m;
  view.frame = frame_;
  view.adaptation = adaptation();
  view.catch_offset_m = request_.catch_offset_m;
  return view;
}

AttemptFacts AttemptRunner::facts(double now_s, const ActVehicles& vehicles) const {
  AttemptFacts f;
  f.catch_it = request_.catch_it;
  f.thrower_task = vehicle_of(vehicles, request_.thrower).sequencer.task();
  f.catcher_task = vehicle_of(vehicles, pa::other_vehicle(request_.thrower)).sequencer.task();
  f.impact = current_.impact_s.has_value();
  f.catcher_end_noted = current_.catcher_end != mission::Reason::none;
  f.now_s = now_s;
  f.throw_start_s = current_.throw_start_s;
  f.throw_duration_s = flown_throw().duration_s();
  // The launch: the estimator's switch to free flight after the throw's manoeuvre began.
  const std::optional<estimation::ModeSwitch> s = estimator_.last_switch();
  if (s && s->to == estimation::PoleMode::free) f.free_flight_call_s = s->event_t_s;
  f.catcher_balancing_since_s = balanced_on_catcher_s_;
  if (last_pole_pose_) f.pole_seen_height_m = last_pole_pose_->p_m.z();
  f.motors_unidentified =
      motors_unidentified(vehicle_of(vehicles, request_.thrower)) ||
      (request_.catch_it && motors_unidentified(vehicle_of(vehicles, pa::other_vehicle(request_.thrower))));
  return f;
}

bool AttemptRunner::motors_unidentified(const ActVehicle& v) const {
  return v.adaptation.motors().refused() && !identifications_.kept(v.id);
}

// Not while the identification flies, nor once it is refused: the attempt ends at the next frame.
bool AttemptRunner::waiting_for_pole(const ActVehicle& v) const {
  return phase_ == AttemptPhase::preparing && v.id == request_.thrower && v.sequencer.task() == Task::hover &&
         !v.adaptation.motors().identifying() && !motors_unidentified(v);
}

void AttemptRunner::update(double now_s, ActVehicles& vehicles) {
  if (phase_ == AttemptPhase::idle) return;
  ActVehicle& thrower = vehicle_of(vehicles, request_.thrower);
  ActVehicle& catcher = vehicle_of(vehicles, pa::other_vehicle(request_.thrower));
  if (thrower.sequencer.task() == Task::balance && thrower.laws.set_point.valid)
    thrower.laws.target_m = throw_origin_target();
  AttemptFacts now = facts(now_s, vehicles);
  const std::uint32_t conditions = attempt_conditions(now, config_.attempt);
  // A catcher lost (no heartbeat, no pose) before the catch is in its failsafe: the catch is off.
  if (conditions & attempt_condition::catcher_lost) current_.catcher_end = catcher.sequencer.last_reason();
  // Before the launch: one step.
  if (phase_bit(phase_) & kBeforeLaunch) {
    const AttemptTransition* row = find_attempt_transition(phase_, conditions);
    if (row && row->to == AttemptPhase::idle) {
      current_.end = row->reason;
      end(now_s, vehicles);
      return;
    }
    const bool thrower_at_origin = (thrower.sequencer.last_conditions() & c::at_target) != 0;
    if (throw_due(phase_, request_.catch_it, thrower_at_origin, catcher.sequencer.task(),
                  catcher.sequencer.last_conditions()))
      thrower.requests |= c::request_throw;
    if (row) phase_ = row->to;
    if (row && phase_ == AttemptPhase::throwing) {
      current_.throw_start_s = thrower.sequencer.task_since_s();
      current_.waiting_xy_m = waiting_xy() + request_.catch_offset_m;
      current_.catch_height_m = catch_height();
      const double catch_instant_s =
          target_throw_ ? target_throw_->plan.catching_instant.t_s : learner_.catch_instant_s();
      catch_.plan(current_, current_.throw_start_s + flown_throw().duration_s() + config_.launch_delay_s,
                  catch_instant_s);
    }
    if (row && phase_ == AttemptPhase::flight) current_.launch_s = now.free_flight_call_s;
  }
  // The catch manoeuvre starts before the launch (T_z ~ 1.8 s against ~1.1 s of flight): plan
  // it from the throw's start on, from the waiting point until the pole flies.
  if (phase_ == AttemptPhase::flight) catch_.retime(now_s, catch_view(catcher), current_);
  if (request_.catch_it && phase_ != AttemptPhase::preparing)
    catch_.update(now_s, catch_view(catcher), current_);
  if ((phase_bit(phase_) & kInFlight) == 0) return;
  // The pole's free flight, from the launch to the impact, for the evaluation of (42).
  record_free_flight(flight_, estimator_.pole(), current_);
  hold_since(balanced_on_catcher_s_, catcher.sequencer.task() == Task::balance, now_s);
  if (request_.thrower_catches_next && balanced_on_catcher_s_ &&
      now_s - *balanced_on_catcher_s_ >= config_.attempt.pass_return_after_s)
    catcher.laws.target_m = throw_start_m(throw_frame(catcher.id));
  // In flight: steps until none applies.
  now = facts(now_s, vehicles);
  const AttemptTransition* row = settle_attempt(phase_, attempt_conditions(now, config_.attempt));
  if (row && row->to == AttemptPhase::idle) {
    current_.end = row->reason;
    if (row->reason == AttemptEnd::caught) current_.caught = true;
    end(now_s, vehicles);
  }
}

void AttemptRunner::end(double now_s, ActVehicles& vehicles) {
  ActVehicle& thrower = vehicle_of(vehicles, request_.thrower);
  ActVehicle& catcher = vehicle_of(vehicles, pa::other_vehicle(request_.thrower));
  catcher.requests &= ~c::request_catch;
  thrower.requests &= ~c::request_throw;
  AttemptFlight flight;
  flight.plan = &flown_throw();
  flight.target_throw = target_throw_ ? &*target_throw_ : nullptr;
  flight.frame = frame_;
  flight.throw_end = throw_end_;
  flight.pole_flight = &flight_;
  flight.pole_model = estimator_.pole_model();
  flight.catch_target_xy_m = catch_.target_xy_m();
  close_attempt(request_, current_, flight, now_s, learner_);
  reports_.push_back(current_);
  phase_ = AttemptPhase::idle;
  catch_.reset();
  // Back to the start: the thrower to where it retreated, the catcher to the next waiting point.
  thrower.laws.target_m = retreat_target();
  catcher.laws.target_m = waiting_target();
}

}  // namespace gs::runtime
