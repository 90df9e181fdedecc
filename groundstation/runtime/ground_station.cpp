#include "groundstation/runtime/ground_station.hpp"

#include <algorithm>
#include <cctype>
#include <stdexcept>

#include "groundstation/planning/catching_instant.hpp"

namespace gs::runtime {
namespace {

namespace c = mission::condition;
using mission::Task;

planning::PlanarLaunchState planned_launch(const planning::ThrowBook& throws) {
  return planning::launch_state_of(throws.plan().trajectory.state_at(throws.problem().duration_s));
}

adaptation::Learner make_learner(const GroundStationConfig& config, const planning::ThrowBook& throws) {
  const model::PoleParams& pole = config.estimator.free_flight.pole;
  const planning::CatchingInstant nominal = planning::find_catching_instant(
      planning::pole_state_at_launch(planning::fig5_launch_state(), pole), pole);
  return adaptation::Learner(
      config.learning, adaptation::nominal_adaptation_settings(pole),
      nominal.found ? nominal.t_s : config.fallback_catch_instant_s, planned_launch(throws),
      adaptation::damped_inverse(throws.end_shift_sensitivity(), config.learning.throw_learning.damping),
      config.learnt, config.adaptation_store_path);
}

// "ARM refused: imu_unhealthy", "ARM not answered": what the vehicle made of a command that failed.
std::string command_failure(const link::CommandOutcome& outcome) {
  const std::string command = pa::proto::command_code_name(outcome.code);
  std::string upper;
  for (const char ch : command) upper += static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
  if (outcome.state == link::CommandState::refused)
    return upper + " refused: " + pa::proto::refuse_reason_name(outcome.reason);
  return upper + " not answered";
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

}  // namespace

GroundStation::GroundStation(link::FrameBus& bus, const GroundStationConfig& config)
    : config_(config),
      link_(bus, {pa::kActVehicles.begin(), pa::kActVehicles.end()}, config.link),
      estimator_(config.estimator),
      throws_(config.limits, config.throw_tracking, config.fig5_throw),
      tasks_(config.tasks, config.limits),
      learner_(make_learner(config, throws_)),
      identifications_({config.rate_loop.design_time_constant_s, config.motor_lag_tolerance_fraction},
                       config.adaptation_store_path, learner_.adaptation_settings()),
      attempt_(config_, estimator_, learner_, throws_, identifications_),
      vehicles_{ActVehicle(pa::kVehicle1, adaptation_settings(config)),
                ActVehicle(pa::kVehicle2, adaptation_settings(config))} {}

const ActVehicle& GroundStation::vehicle_of(pa::VehicleId id) const {
  if (!pa::is_act_vehicle(id)) throw std::out_of_range("no vehicle with node " + std::to_string(id.node()));
  return vehicles_[pa::act_slot(id)];
}

control::ThrowFrame GroundStation::throw_frame(pa::VehicleId thrower) const {
  return attempt_.throw_frame(vehicle_of(thrower).id);
}

void GroundStation::request_all(std::uint32_t request) {
  for (ActVehicle& v : vehicles_) v.requests |= request;
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
  return attempt_.request(request, vehicles_, [this](pa::VehicleId v) { return thrust_of(v); });
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
    ActVehicle& v = vehicle_of(pa::VehicleId(m->node));
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
  for (ActVehicle& v : vehicles_) {
    v.adaptation.settle([&](const link::CommandHandle& h) { return link_.command_state(h); });
    const bool at_target = (v.sequencer.last_conditions() & c::at_target) != 0;
    set_on_board(v, v.adaptation.identify(now_s, v.sequencer.task(), at_target, identifications_), now_s);
  }
  for (ActVehicle& v : vehicles_) {
    if (!v.commands.pending()) continue;
    const link::CommandOutcome outcome = link_.command_outcome(*v.commands.pending());
    if (v.commands.settle(outcome.state, v.sequencer.task() == Task::arming))
      v.commands.sent(link_.send_command(v.id, pa::proto::CommandCode::arm, 0, now_s));
    else if (outcome.state != link::CommandState::pending && outcome.state != link::CommandState::accepted)
      v.command_failure = command_failure(outcome);  // failed just now
  }
}

mission::ConditionFacts GroundStation::facts(const ActVehicle& v, double now_s) const {
  const VehicleView vehicle{v.id,
                            v.requests,
                            v.commands.failed(),
                            v.sequencer.task(),
                            v.sequencer.task_since_s(),
                            v.last_pose_s,
                            v.laws.target_m,
                            v.laws.set_point.position_m};
  return condition_facts(vehicle, link_.status(v.id), estimator_, attempt_.view(now_s), now_s);
}

void GroundStation::enter(ActVehicle& v, double now_s) {
  const Task task = v.sequencer.task();
  const bool estimated = estimator_.vehicle_initialised(v.id);
  TaskEntryContext context;
  context.reason = v.sequencer.last_reason();
  context.here_m = estimated ? estimator_.vehicle(v.id).state.p_m : v.laws.target_m;
  if (estimated) context.vertical_speed_mps = estimator_.vehicle(v.id).state.v_mps.z();
  context.vehicle_mode = link_.status(v.id).mode;
  context.identify_motors = config_.identify_motors;
  attempt_.entering(task, now_s, context);
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
  attempt_.entered(v, estimated, now_s, context.here_m);
}

// A task's law on the estimate predicted to when the command acts (latency compensation).
void GroundStation::fly(ActVehicle& v, double now_s, double dt_s) {
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
  if (task == Task::wait) f.waiting_target_m = attempt_.waiting_target();
  f.motor_lead_s =
      std::max(0.0, v.adaptation.motors().equalised_s() - config_.rate_loop.design_time_constant_s);
  const TaskCommand command = tasks_.command(v.laws, f, attempt_.flown());
  attempt_.commanded(command, now_s);
  if (command.input) send(v, *command.input, now_s);
}

void GroundStation::on_mocap(const estimation::MocapFrame& frame, double now_s) {
  const double dt_s = frame_interval_s(last_mocap_s_, now_s, config_.frame_interval);
  last_mocap_s_ = now_s;
  for (const ActVehicle& v : vehicles_) estimator_.set_throwing(v.id, v.sequencer.task() == Task::throwing);
  estimator_.update(frame);
  for (ActVehicle& v : vehicles_) {
    const std::optional<estimation::MocapPose>& pose = frame.vehicle[pa::act_slot(v.id)];
    if (!pose) continue;
    v.last_pose_s = now_s;
    if (const std::optional<double> sigma = v.adaptation.on_pose(frame.t_s, now_s, *pose, v.sequencer.task()))
      estimator_.set_pole_measurement_sigma(v.id, *sigma, *sigma);
  }
  if (frame.pole) attempt_.pole_seen(*frame.pole);
  // The estimator predicted, states only, to when the commands act (latency compensation).
  ahead_.emplace(estimator_.predicted(std::max(estimator_.time(), now_s + config_.command_lead_s)));

  attempt_.update(now_s, vehicles_);
  for (ActVehicle& v : vehicles_) keep_inside_volume(v);
  for (ActVehicle& v : vehicles_) {
    const Task before = v.sequencer.task();
    if (v.sequencer.step(mission::condition_word(facts(v, now_s), config_.conditions), now_s)) {
      if (events_.size() < kEventLogCapacity) {
        const mission::Reason reason = v.sequencer.last_reason();
        events_.push_back({now_s, v.id, before, v.sequencer.task(), reason,
                           reason == mission::Reason::arm_failed ? v.command_failure : std::string()});
      }
      enter(v, now_s);
    }
    fly(v, now_s, dt_s);
  }
}

// A flying vehicle found beyond the arena's walls, floor or ceiling lands where it is, as if the
// operator had asked: the descent is the mission table's one way down under control, entered only
// on a land request (vehicle_sequencer_test), and it clears the request.
void GroundStation::keep_inside_volume(ActVehicle& v) {
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
void GroundStation::send(ActVehicle& v, const model::VehicleInput& u, double now_s) {
  const model::VehicleInput sent = link_.send_setpoint(v.id, v.adaptation.setpoint(u, now_s));
  const double t_acts_s = now_s + config_.command_lead_s;
  estimator_.set_command(v.id, t_acts_s, v.adaptation.delivered(sent, now_s, t_acts_s));
}

void GroundStation::set_on_board(ActVehicle& v, const std::vector<OnBoardCommand>& commands, double now_s) {
  for (const OnBoardCommand& command : commands)
    v.adaptation.sent(command, link_.send_command(v.id, command.code, command.argument, now_s));
}

// The vehicle's gyro-held attitude set back onto motion capture's (estimation/onboard_tilt.hpp)
// while the ground station flies it: its hold, its failsafe and a landing's end fly on it.
void GroundStation::correct_onboard_tilt(ActVehicle& v, const pa::proto::TelemetryAttitude& attitude,
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

bool GroundStation::waiting_for_pole(pa::VehicleId vehicle) const {
  return attempt_.waiting_for_pole(vehicle_of(vehicle));
}

}  // namespace gs::runtime
