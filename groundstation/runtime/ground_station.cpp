#include "groundstation/runtime/ground_station.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "groundstation/adaptation/throw_evaluation.hpp"
#include "groundstation/planning/catching_instant.hpp"

namespace gs::runtime {
namespace {

namespace c = mission::condition;
using mission::Task;

planning::InputLimits input_limits(const model::VehicleLimits& l) {
  return {l.a_q_min_mps2, l.a_q_max_mps2, l.omega_max_radps};
}

planning::PlanarLaunchState planned_launch(const planning::ThrowBook& throws) {
  return planning::launch_state_of(throws.plan().trajectory.state_at(throws.problem().duration_s));
}

adaptation::Learner make_learner(const GroundStationConfig& config, const planning::ThrowBook& throws) {
  const model::PoleParams& pole = config.estimator.free_flight.pole;
  const planning::CatchingInstant nominal = planning::find_catching_instant(
      planning::pole_state_at_launch(planning::fig5_launch_state(), pole), pole);
  return adaptation::Learner(config.learning, adaptation::nominal_adaptation_settings(pole),
                             nominal.found ? nominal.t_s : config.fallback_catch_instant_s,
                             planned_launch(throws),
                             adaptation::damped_inverse(adaptation::throw_sensitivity(throws.tracker()),
                                                        config.learning.throw_learning.damping),
                             config.learnt, config.adaptation_store_path);
}

VehicleAdaptationSettings adaptation_settings(const GroundStationConfig& config) {
  return {config.thrust_gain,
          config.compensate_thrust_gain,
          config.thrust_gain_min_height_m,
          config.tasks.pole_weight_mps2,
          config.rate_loop,
          config.rate_response,
          config.pole_trust,
          config.limits,
          config.airframe_thrust_max_mps2};
}

ThrustAdmission thrust_admission(const GroundStationConfig& config) {
  return {config.airframe_thrust_max_mps2, config.min_thrust_fraction, config.battery_reference_voltage_V,
          pa::kGravity_mps2 + config.catching.a_max_mps2, config.tasks.pole_weight_mps2 / pa::kGravity_mps2};
}

}  // namespace

GroundStation::GroundStation(link::FrameBus& bus, const GroundStationConfig& config)
    : config_(config),
      link_(bus, {pa::kActVehicles.begin(), pa::kActVehicles.end()}, config.link),
      estimator_(config.estimator),
      throws_(config.limits, config.throw_tracking),
      tasks_(config.tasks, config.limits),
      learner_(make_learner(config, throws_)),
      identifications_({config.rate_loop.design_time_constant_s, config.motor_lag_tolerance_fraction},
                       config.adaptation_store_path, learner_.adaptation_settings()),
      catch_(config.catching, input_limits(config.limits)),
      vehicles_{Vehicle(pa::kVehicle1, adaptation_settings(config)),
                Vehicle(pa::kVehicle2, adaptation_settings(config))} {
  frame_ = throw_frame(pa::kVehicle1);
}

const GroundStation::Vehicle& GroundStation::vehicle_of(pa::VehicleId id) const {
  if (!pa::is_act_vehicle(id)) throw std::out_of_range("no vehicle with node " + std::to_string(id.node()));
  return vehicles_[pa::act_slot(id)];
}

control::ThrowFrame GroundStation::throw_frame(pa::VehicleId thrower) const {
  return throw_frame_of(vehicle_of(thrower).id, config_.throw_origin_m, config_.throw_yaw_rad, adaptation());
}
std::optional<Eigen::Vector3d> GroundStation::aimed_m() const {
  return target_throw_ ? std::optional(target_throw_->plan.target_m) : std::nullopt;
}
Eigen::Vector2d GroundStation::waiting_xy() const { return catch_point_xy(frame_, adaptation(), aimed_m()); }
double GroundStation::catch_height() const {
  return floored_catch_height_m(
      catch_height_m(frame_, adaptation(), aimed_m(),
                     catch_energy_.height_offset_m(pa::other_vehicle(request_.thrower))),
      config_.catching);
}

// The pole's energy right after the impact on `catcher`'s plate (41), from its last free-flight
// estimate and the plate's velocity; the catcher's catching height learns from it
// (adaptation/catch_energy.hpp).
void GroundStation::measure_impact_energy(const Vehicle& catcher) {
  if (flight_.empty()) return;
  const double energy_J = adaptation::post_impact_energy_J(
      flight_.back().state, estimator_.plate(catcher.id).v_mps, estimator_.pole_model());
  current_.energy_after_impact_J = energy_J;
  catch_energy_.learn(catcher.id, energy_J, learner_.adaptation_settings().target_energy_J);
}
Eigen::Vector3d GroundStation::waiting_target() const {
  const Eigen::Vector2d xy = waiting_xy() + request_.catch_offset_m;
  return Eigen::Vector3d(xy.x(), xy.y(), catch_.z_manoeuvre(catch_height()).start_height_m());
}
Eigen::Vector3d GroundStation::throw_origin_target() const { return throw_start_m(frame_); }
Eigen::Vector3d GroundStation::retreat_target() const {
  Eigen::Vector3d target = throw_origin_target();
  if (request_.thrower_catches_next) target.z() = std::max(target.z(), waiting_target().z());
  return target;
}
const planning::ThrowTrajectory& GroundStation::flown_throw() const {
  return target_throw_ ? target_throw_->plan.plan.trajectory : throws_.plan().trajectory;
}
const planning::ThrowTracker& GroundStation::flown_tracker() const {
  return target_throw_ ? target_throw_->tracker : throws_.tracker();
}

void GroundStation::request_all(std::uint32_t request) {
  for (Vehicle& v : vehicles_) v.requests |= request;
}
void GroundStation::request_kill(std::optional<pa::VehicleId> vehicle, pa::proto::KillReason reason) {
  if (vehicle) {
    link_.send_kill(vehicle_of(*vehicle).id, reason);
  } else {
    link_.send_kill_all(reason);
  }
}

VehicleThrust GroundStation::thrust_of(pa::VehicleId vehicle) const {
  const link::VehicleLinkStatus& status = link_.status(vehicle);
  return {vehicle, vehicle_of(vehicle).adaptation.thrust_gain().gain(),
          status.vehicle_status.valid ? 1e-3 * status.vehicle_status.value.battery_mv : 0.0};
}

double GroundStation::thrust_ceiling_mps2(pa::VehicleId vehicle) const {
  return runtime::thrust_ceiling_mps2(thrust_of(vehicle), thrust_admission(config_));
}

pa::VehicleId GroundStation::stronger_thrower(pa::VehicleId preferred) const {
  return runtime::stronger_thrower(thrust_of(preferred), thrust_of(pa::other_vehicle(preferred)),
                                   thrust_admission(config_));
}

bool GroundStation::pack_spent(pa::VehicleId vehicle) const {
  const ThrustAdmission admission = thrust_admission(config_);
  return runtime::pack_spent(thrust_of(vehicle),
                             peak_thrust_mps2(throws_.plan().trajectory, admission.pole_to_vehicle_mass),
                             config_.pack_swap, admission);
}

bool GroundStation::request_attempt(const AttemptRequest& request) {
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
  refusal_kind_ = Refusal::none;
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
  Vehicle& thrower = vehicle_of(request.thrower);
  thrower.laws.target_m = throw_origin_target();
  if (request.catch_it) other(thrower).requests |= c::request_catch;
  return true;
}

void GroundStation::on_frame(const pa::proto::Frame& frame, double now_s) {
  // The link's vehicles are the act's. The rates each vehicle reports, for its identification
  // flight; its attitude, against motion capture's.
  const std::optional<pa::proto::Message> m = link_.on_frame(frame, now_s);
  if (m && m->type == pa::proto::Type::telemetry_rates)
    vehicle_of(pa::VehicleId(m->node))
        .adaptation.identification_flight()
        .telemetry(now_s, m->telemetry_rates);
  if (m && m->type == pa::proto::Type::telemetry_attitude)
    correct_onboard_tilt(vehicle_of(pa::VehicleId(m->node)), m->telemetry_attitude, now_s);
  // A vehicle that reports its pack's voltage compensates for it on board (ThrustGainConfig).
  if (m && m->type == pa::proto::Type::telemetry_status) {
    Vehicle& v = vehicle_of(pa::VehicleId(m->node));
    v.adaptation.set_voltage_compensated(thrust_of(v.id).battery_V > 0.0);
  }
  for (const link::ImpactReport& r : link_.take_impacts()) {
    if (impacts_.size() < kEventLogCapacity) impacts_.push_back(r);
    if (pa::is_act_vehicle(r.vehicle)) estimator_.report_impact(r.vehicle, r.t_s);
  }
}

// A vehicle that landed arms only from disarmed: its DISARM, once accepted, is followed by the ARM.
void GroundStation::tick(double now_s) {
  link_.tick(now_s);
  for (Vehicle& v : vehicles_) {
    v.adaptation.settle([&](const link::CommandHandle& h) { return link_.command_state(h); });
    const bool at_target = (v.sequencer.last_conditions() & c::at_target) != 0;
    set_on_board(v, v.adaptation.identify(now_s, v.sequencer.task(), at_target, identifications_), now_s);
  }
  for (Vehicle& v : vehicles_) {
    if (v.commands.pending() &&
        v.commands.settle(link_.command_state(*v.commands.pending()), v.sequencer.task() == Task::arming))
      v.commands.sent(link_.send_command(v.id, pa::proto::CommandCode::arm, 0, now_s));
  }
}

mission::ConditionFacts GroundStation::facts(const Vehicle& v, double now_s) const {
  const VehicleView vehicle{v.id,
                            v.requests,
                            v.commands.failed(),
                            v.sequencer.task(),
                            v.sequencer.task_since_s(),
                            v.last_pose_s,
                            v.laws.target_m,
                            v.laws.set_point.position_m};
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
  return condition_facts(vehicle, link_.status(v.id), estimator_, attempt, now_s);
}

void GroundStation::enter(Vehicle& v, double now_s) {
  const Task task = v.sequencer.task();
  const bool estimated = estimator_.vehicle_initialised(v.id);
  TaskEntryContext context;
  context.reason = v.sequencer.last_reason();
  context.here_m = estimated ? estimator_.vehicle(v.id).state.p_m : v.laws.target_m;
  if (estimated) context.vertical_speed_mps = estimator_.vehicle(v.id).state.v_mps.z();
  context.vehicle_mode = link_.status(v.id).mode;
  context.retreat_target_m = retreat_target();
  context.catch_target_xy_m = catch_.target_xy_m();
  context.identify_motors = config_.identify_motors;
  if (task == Task::catching) {
    current_.catch_start_s = now_s;
    context.catch_window_s = catch_.start(now_s, catch_height(), config_.catch_window_margin_s);
  }
  const TaskEntry entry =
      enter_task(task, v.laws, v.requests, context,
                 {config_.take_off_height_m, config_.clear_distance_m, config_.land_handover_height_m});
  if (task == Task::arming) {
    v.commands.arming(entry.arm_after_disarm);
    set_on_board(v, v.adaptation.at_arming(identifications_), now_s);
  }
  if (entry.command)
    v.commands.sent(link_.send_command(v.id, entry.command->code, entry.command->argument, now_s));
  if (entry.start_identification) v.adaptation.start_identification(now_s);
  const Eigen::Vector3d& here = context.here_m;
  if (task == Task::balance) balanced_since_s_.reset();
  // Where on the plate the pole rests as the throw starts (see the throwing task's control).
  if (task == Task::throwing)
    resting_offset_m_ = estimated && estimator_.pole().valid
                            ? resting_offset_m(estimator_.plate(v.id), estimator_.pole().state,
                                               estimator_.pole_model().half_length_m)
                            : Eigen::Vector3d::Zero();
  if (task == Task::rebalance && !current_.impact_s) measure_impact_energy(v);  // the first impact
  note_task_entry(request_, phase_ != AttemptPhase::idle, current_, v.id, task, v.sequencer.last_reason(),
                  now_s, here);
}

// A task's law on the estimate predicted to when the command acts (latency compensation).
void GroundStation::fly(Vehicle& v, double now_s, double dt_s) {
  const Task task = v.sequencer.task();
  if (!flies_law(task)) {
    if (const std::optional<model::VehicleInput> u = fixed_command(task)) send(v, *u, now_s);
    return;
  }
  if (!estimator_.vehicle_initialised(v.id)) return;
  TaskFrame f;
  f.task = task;
  f.now_s = now_s;
  f.t_act_s = std::max(estimator_.time(), now_s + config_.command_lead_s);
  f.dt_s = dt_s;
  f.task_since_s = v.sequencer.task_since_s();
  f.vehicle = ahead_->vehicle(v.id);
  f.pole = ahead_->pole();
  f.plate = ahead_->plate(v.id);
  f.half_length_m = ahead_->pole_model().half_length_m;
  if (task == Task::wait) f.waiting_target_m = waiting_target();
  f.motor_lead_s =
      std::max(0.0, v.adaptation.motors().equalised_s() - config_.rate_loop.design_time_constant_s);
  FlownThrow flown{&flown_throw(),
                   &flown_tracker(),
                   frame_,
                   resting_offset_m_,
                   target_throw_ ? nullptr : &learner_.throw_correction(request_.thrower),
                   nullptr,
                   catch_.start_s()};
  if (catch_.trajectory()) flown.catch_trajectory = &*catch_.trajectory();
  flown.catch_height_shift = &catch_.height_shift();
  const TaskCommand command = tasks_.command(v.laws, f, flown);
  if (command.pole_settled) hold_since(balanced_since_s_, *command.pole_settled, now_s);
  if (command.throw_end) throw_end_ = command.throw_end;
  if (command.input) send(v, *command.input, now_s);
}

void GroundStation::on_mocap(const estimation::MocapFrame& frame, double now_s) {
  const double dt_s = frame_interval_s(last_mocap_s_, now_s, config_.frame_interval);
  last_mocap_s_ = now_s;
  estimator_.update(frame);
  for (Vehicle& v : vehicles_) {
    const std::optional<estimation::MocapPose>& pose = frame.vehicle[pa::act_slot(v.id)];
    if (!pose) continue;
    v.last_pose_s = now_s;
    if (const std::optional<double> sigma = v.adaptation.on_pose(frame.t_s, now_s, *pose, v.sequencer.task()))
      estimator_.set_pole_measurement_sigma(v.id, *sigma, *sigma);
  }
  if (frame.pole) last_pole_pose_ = *frame.pole;
  // The estimator predicted, states only, to when the commands act (latency compensation).
  ahead_.emplace(estimator_.predicted(std::max(estimator_.time(), now_s + config_.command_lead_s)));

  update_attempt(now_s);
  for (Vehicle& v : vehicles_) keep_inside_volume(v);
  for (Vehicle& v : vehicles_) {
    const Task before = v.sequencer.task();
    if (v.sequencer.step(mission::condition_word(facts(v, now_s), config_.conditions), now_s)) {
      if (events_.size() < kEventLogCapacity)
        events_.push_back({now_s, v.id, before, v.sequencer.task(), v.sequencer.last_reason()});
      enter(v, now_s);
    }
    fly(v, now_s, dt_s);
  }
}

// A flying vehicle found beyond the arena's walls, floor or ceiling lands where it is, as if the
// operator had asked: the descent is the mission table's one way down under control, entered only
// on a land request (vehicle_sequencer_test), and it clears the request.
void GroundStation::keep_inside_volume(Vehicle& v) {
  if (!config_.arena_volume || !estimator_.vehicle_initialised(v.id)) return;
  const Task task = v.sequencer.task();
  if ((mission::kAirborne & mission::task_bit(task)) == 0 || task == Task::descend ||
      (v.requests & c::request_land))
    return;
  if (!outside_volume(estimator_.vehicle(v.id).state.p_m, *config_.arena_volume)) return;
  v.requests |= c::request_land;
  ++volume_breaches_;
}

// The estimator's model is told what the vehicle delivers (vehicle_adaptation.hpp).
void GroundStation::send(Vehicle& v, const model::VehicleInput& u, double now_s) {
  const model::VehicleInput sent = link_.send_setpoint(v.id, v.adaptation.setpoint(u, now_s));
  const double t_acts_s = now_s + config_.command_lead_s;
  estimator_.set_command(v.id, t_acts_s, v.adaptation.delivered(sent, now_s, t_acts_s));
}

void GroundStation::set_on_board(Vehicle& v, const std::vector<OnBoardCommand>& commands, double now_s) {
  for (const OnBoardCommand& command : commands)
    v.adaptation.sent(command, link_.send_command(v.id, command.code, command.argument, now_s));
}
// The vehicle's gyro-held attitude set back onto motion capture's (estimation/onboard_tilt.hpp)
// while the ground station flies it: its hold, its failsafe and a landing's end fly on it.
void GroundStation::correct_onboard_tilt(Vehicle& v, const pa::proto::TelemetryAttitude& attitude,
                                         double now_s) {
  const link::VehicleLinkStatus& status = link_.status(v.id);
  if (status.mode != pa::proto::Mode::flying || !flies_law(v.sequencer.task()) ||
      !estimator_.vehicle_initialised(v.id) || !status.rates.valid)
    return;
  const model::VehicleState& s = estimator_.vehicle(v.id).state;
  const Eigen::Quaterniond measured(model::rotation_inertial_from_body(s.phi_rad, s.theta_rad, s.psi_rad));
  const auto& q = attitude.quaternion;
  const Eigen::Quaterniond onboard(q[0], q[1], q[2], q[3]);
  const double rate_radps = Eigen::Map<const Eigen::Vector3f>(status.rates.value.rate_radps.data()).norm();
  if (const std::optional<OnBoardCommand> command =
          v.adaptation.tilt_correction(now_s, onboard, measured, rate_radps))
    set_on_board(v, {*command}, now_s);
}

CatchView GroundStation::catch_view(const Vehicle& catcher) const {
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

AttemptFacts GroundStation::attempt_facts(double now_s) const {
  AttemptFacts f;
  f.catch_it = request_.catch_it;
  f.thrower_task = vehicle_of(request_.thrower).sequencer.task();
  f.catcher_task = vehicle_of(pa::other_vehicle(request_.thrower)).sequencer.task();
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
  return f;
}

bool GroundStation::waiting_for_pole(pa::VehicleId vehicle) const {
  const Vehicle& v = vehicle_of(vehicle);
  return phase_ == AttemptPhase::preparing && vehicle == request_.thrower &&
         v.sequencer.task() == Task::hover && !v.adaptation.motors().identifying();
}

void GroundStation::update_attempt(double now_s) {
  if (phase_ == AttemptPhase::idle) return;
  Vehicle& thrower = vehicle_of(request_.thrower);
  Vehicle& catcher = other(thrower);
  if (thrower.sequencer.task() == Task::balance && thrower.laws.set_point.valid)
    thrower.laws.target_m = throw_origin_target();
  AttemptFacts facts = attempt_facts(now_s);
  const std::uint32_t conditions = attempt_conditions(facts, config_.attempt);
  // A catcher lost (no heartbeat, no pose) before the catch is in its failsafe: the catch is off.
  if (conditions & attempt_condition::catcher_lost) current_.catcher_end = catcher.sequencer.last_reason();
  // Before the launch: one step.
  if (phase_bit(phase_) & kBeforeLaunch) {
    const AttemptTransition* row = find_attempt_transition(phase_, conditions);
    if (row && row->to == AttemptPhase::idle) {
      end_attempt(now_s);
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
    if (row && phase_ == AttemptPhase::flight) current_.launch_s = facts.free_flight_call_s;
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
  facts = attempt_facts(now_s);
  const AttemptTransition* row = settle_attempt(phase_, attempt_conditions(facts, config_.attempt));
  if (row && row->to == AttemptPhase::idle) {
    if (row->reason == AttemptEnd::caught) current_.caught = true;
    end_attempt(now_s);
  }
}

void GroundStation::end_attempt(double now_s) {
  Vehicle& thrower = vehicle_of(request_.thrower);
  Vehicle& catcher = other(thrower);
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
