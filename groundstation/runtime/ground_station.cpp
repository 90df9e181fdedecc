#include "groundstation/runtime/ground_station.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "groundstation/adaptation/throw_evaluation.hpp"
#include "groundstation/control/balancing_lqr.hpp"
#include "groundstation/control/hover_lqr.hpp"
#include "groundstation/planning/catching_instant.hpp"
#include "groundstation/planning/throw_command.hpp"

namespace gs::runtime {
namespace {

namespace c = mission::condition;
using mission::Task;

// The pole's tilt from the vertical (either end up).
double tilt_rad(const model::PoleState& s) { return std::acos(std::min(1.0, std::abs(s.n.z()))); }

// The pole's end nearest the plate, from the latest pose.
double pole_end_from_plate_m(const estimation::MocapPose& pose, const Eigen::Vector3d& plate_m,
                             double half_length_m) {
  const Eigen::Vector3d n = pose.q * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d a = pose.p_m + half_length_m * n, b = pose.p_m - half_length_m * n;
  return std::min((a - plate_m).norm(), (b - plate_m).norm());
}

// Where the pole rests: its end at the plate (the on-vehicle filter estimates where on the plate
// it landed), moving with the plate. A pole caught 1.6 cm off the plate's centre, balanced about
// the centre, read as a 0.025 rad tilt, which the balancing LQR held against a 0.46 m position
// error (measured: the catcher of a pass could not reach its throw's origin). The throw keeps
// the plate's centre: its plan assumes the pole there, and the filter's offset moves while the
// throw accelerates (flown about the resting end, the learnt throw's error after 10 throws was
// 0.105 against 0.078, throw_learning_test).
control::Pivot resting_pivot(const estimation::PlateKinematics& plate, const model::PoleState& pole,
                             double half_length_m) {
  const Eigen::Vector3d a = pole.p_m + half_length_m * pole.n, b = pole.p_m - half_length_m * pole.n;
  return {(a - plate.p_m).norm() < (b - plate.p_m).norm() ? a : b, plate.v_mps};
}

planning::InputLimits input_limits(const model::VehicleLimits& l) {
  return {l.a_q_min_mps2, l.a_q_max_mps2, l.omega_max_radps};
}

control::LqrGain designed(const control::LqrGain& gain) {
  if (!gain.ok) throw std::runtime_error("the LQR design failed");
  return gain;
}

planning::PlanarLaunchState planned_launch(const planning::ThrowBook& throws) {
  return adaptation::launch_state_of(throws.plan().trajectory.state_at(throws.problem().duration_s));
}

adaptation::Learner make_learner(const GroundStationConfig& config, const planning::ThrowBook& throws) {
  const model::PoleParams& pole = config.estimator.free_flight.pole;
  const planning::CatchingInstant nominal = planning::find_catching_instant(
      planning::pole_state_at_launch(planning::fig5_launch_state(), pole), pole);
  return adaptation::Learner(config.learning, adaptation::nominal_adaptation_settings(pole),
                             nominal.found ? nominal.t_s : 0.8, planned_launch(throws),
                             adaptation::damped_inverse(adaptation::throw_sensitivity(throws.tracker()),
                                                        config.learning.throw_learning.damping),
                             config.learnt, config.adaptation_store_path);
}

}  // namespace

GroundStation::GroundStation(link::FrameBus& bus, const GroundStationConfig& config)
    : config_(config),
      link_(bus, {pa::kActVehicles.begin(), pa::kActVehicles.end()}, config.link),
      estimator_(config.estimator),
      throws_(config.limits, config.throw_tracking),
      hover_(designed(control::hover_lqr())),
      balancing_(designed(control::balancing_lqr())),
      learner_(make_learner(config, throws_)),
      identifications_({config.rate_loop.design_time_constant_s, config.motor_lag_tolerance_fraction},
                       config.adaptation_store_path, learner_.adaptation_settings()),
      catch_(config.catching, input_limits(config.limits)) {
  frame_ = throw_frame(pa::kVehicle1);
  for (Vehicle& v : vehicles_) {
    v.thrust_gain = estimation::ThrustGainEstimator(config_.thrust_gain);
    v.identification =
        IdentificationFlight(estimation::RateResponseIdentifier(config_.rate_loop, config_.rate_response));
    v.equalised_s = config_.rate_loop.design_time_constant_s;
  }
}

GroundStation::Vehicle& GroundStation::vehicle_of(pa::VehicleId id) {
  if (!pa::is_act_vehicle(id)) throw std::out_of_range("no vehicle with node " + std::to_string(id.node()));
  return vehicles_[pa::act_slot(id)];
}
const GroundStation::Vehicle& GroundStation::vehicle_of(pa::VehicleId id) const {
  if (!pa::is_act_vehicle(id)) throw std::out_of_range("no vehicle with node " + std::to_string(id.node()));
  return vehicles_[pa::act_slot(id)];
}

mission::Task GroundStation::task(pa::VehicleId id) const { return vehicle_of(id).sequencer.task(); }
const estimation::ThrustGainEstimator& GroundStation::thrust_gain(pa::VehicleId id) const {
  return vehicle_of(id).thrust_gain;
}
const std::optional<estimation::IdentificationResult>& GroundStation::motor_identification(
    pa::VehicleId id) const {
  return vehicle_of(id).identified;
}
double GroundStation::equalised_motor_time_constant_s(pa::VehicleId id) const {
  return vehicle_of(id).equalised_s;
}

control::ThrowFrame GroundStation::throw_frame(pa::VehicleId thrower) const {
  const control::ThrowFrame first{config_.throw_origin_m, config_.throw_yaw_rad};
  if (vehicle_of(thrower).id == pa::kVehicle1) return first;
  const Eigen::Vector2d back = first.to_arena_xy(adaptation().waiting_xy_m);
  return {Eigen::Vector3d(back.x(), back.y(), config_.throw_origin_m.z()), config_.throw_yaw_rad + M_PI};
}

// The adaptation's values are the throw's (its frame's); the runtime flies in the arena's. A
// throw to a target comes down on the target.
Eigen::Vector2d GroundStation::waiting_xy() const {
  if (target_throw_) return target_throw_->plan.target_m.head<2>();
  return frame_.to_arena_xy(adaptation::compensate_offset_bias(adaptation().waiting_xy_m, adaptation()));
}
double GroundStation::catch_height() const {
  const double offset_m = catch_energy_.height_offset_m(pa::other_vehicle(request_.thrower));
  if (target_throw_) return target_throw_->plan.target_m.z() + offset_m;
  return frame_.origin_m.z() + adaptation().catch_height_m + offset_m;
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
Eigen::Vector3d GroundStation::throw_origin_target() const {
  return frame_.origin_m - pa::kPlateHeightAboveCg_m * Eigen::Vector3d::UnitZ();
}
const planning::ThrowTrajectory& GroundStation::flown_throw() const {
  return target_throw_ ? target_throw_->plan.plan.trajectory : throws_.plan().trajectory;
}
const planning::ThrowTracker& GroundStation::flown_tracker() const {
  return target_throw_ ? target_throw_->tracker : throws_.tracker();
}

void GroundStation::request_take_off() {
  for (Vehicle& v : vehicles_) v.requests |= c::request_take_off;
}
void GroundStation::request_land() {
  for (Vehicle& v : vehicles_) v.requests |= c::request_land;
}
void GroundStation::request_abort() {
  for (Vehicle& v : vehicles_) v.requests |= c::request_abort;
}
void GroundStation::request_kill(std::optional<pa::VehicleId> vehicle, pa::proto::KillReason reason) {
  if (vehicle) {
    link_.send_kill(vehicle_of(*vehicle).id, reason);
  } else {
    link_.send_kill_all(reason);
  }
}

std::string GroundStation::thrust_shortfall(const Vehicle& v, double needed_mps2, const char* part) const {
  const double k = v.thrust_gain.gain();
  const link::VehicleLinkStatus& status = link_.status(v.id);
  const double volts = status.vehicle_status.valid ? 1e-3 * status.vehicle_status.value.battery_mv : 0.0;
  // No voltage reported (0: none, or no compensation on board): the ceiling is k's alone.
  const double sag =
      volts > 0.0 ? std::min(1.0, std::pow(volts / config_.battery_reference_voltage_V, 2.0)) : 1.0;
  const double most_mps2 = k * sag * config_.airframe_thrust_max_mps2;
  if (most_mps2 >= config_.min_thrust_fraction * needed_mps2) return {};
  char at[32] = "";
  if (volts > 0.0) std::snprintf(at, sizeof at, " at %.2f V", volts);
  char text[240];
  std::snprintf(
      text, sizeof text,
      "vehicle %u is too weak to %s: thrust gain %.2f%s gives %.1f m/s^2 at most, the %s needs %.1f",
      static_cast<unsigned>(v.id.node()), part, k, at, most_mps2, part,
      config_.min_thrust_fraction * needed_mps2);
  return text;
}

std::string_view GroundStation::refusal_name(Refusal refusal) {
  switch (refusal) {
    case Refusal::none: return "none";
    case Refusal::busy: return "ground_station_busy";
    case Refusal::not_of_act: return "not_of_act";
    case Refusal::target_not_planned: return "target_throw_not_planned";
    case Refusal::too_weak: return "vehicle_too_weak";
  }
  return "?";
}

bool GroundStation::request_attempt(const AttemptRequest& request) {
  const auto refuse = [&](Refusal kind, std::string why) {
    refusal_kind_ = kind;
    refusal_ = std::move(why);
    return false;
  };
  if (phase_ != AttemptPhase::idle) return refuse(Refusal::busy, "an attempt is running");
  if (!pa::is_act_vehicle(request.thrower))
    return refuse(Refusal::not_of_act,
                  "vehicle " + std::to_string(request.thrower.node()) + " is not of the act");
  const control::ThrowFrame frame = throw_frame(request.thrower);
  std::optional<planning::TargetThrow> target_throw;
  if (request.target_xy_m) {
    const Eigen::Vector3d target(request.target_xy_m->x(), request.target_xy_m->y(),
                                 frame.origin_m.z() + adaptation().catch_height_m);
    target_throw = throws_.plan_to(frame.origin_m, target, learner_.target_miss_m());
    if (!target_throw)
      return refuse(Refusal::target_not_planned, "the throw to the target cannot be planned");
  }
  const planning::ThrowTrajectory& flown =
      target_throw ? target_throw->plan.plan.trajectory : throws_.plan().trajectory;
  double peak_mps2 = 0.0;
  for (const model::PlanarInput<double>& u : flown.input)
    peak_mps2 = std::max(peak_mps2, u(model::planar::kThrust));
  if (std::string why = thrust_shortfall(vehicle_of(request.thrower), peak_mps2, "throw"); !why.empty())
    return refuse(Refusal::too_weak, why);
  if (request.catch_it) {
    const double needed_mps2 = pa::kGravity_mps2 + config_.catching.a_max_mps2;
    if (std::string why = thrust_shortfall(other(vehicle_of(request.thrower)), needed_mps2, "catch");
        !why.empty())
      return refuse(Refusal::too_weak, why);
  }
  refusal_kind_ = Refusal::none;
  refusal_.clear();
  target_throw_ = std::move(target_throw);
  frame_ = target_throw_ ? control::ThrowFrame{frame.origin_m, target_throw_->plan.yaw_rad} : frame;
  request_ = request;
  phase_ = AttemptPhase::preparing;
  current_ = AttemptReport{};
  current_.number = ++attempt_count_;
  current_.throw_correction = learner_.throw_correction().end_shift;
  throw_end_.reset();
  flight_.clear();
  catch_.reset();
  balanced_since_s_.reset();
  if (target_throw_) current_.target_m = target_throw_->target_m;
  Vehicle& thrower = vehicle_of(request.thrower);
  thrower.target_m = throw_origin_target();
  if (request.catch_it) other(thrower).requests |= c::request_catch;
  return true;
}

void GroundStation::on_frame(const pa::proto::Frame& frame, double now_s) {
  link_.on_frame(frame, now_s);
  // The rates each vehicle reports, for its identification flight.
  const std::uint8_t node = pa::proto::id_node(frame.id);
  pa::proto::Message m;
  if (pa::proto::id_type(frame.id) == static_cast<std::uint8_t>(pa::proto::Type::telemetry_rates) &&
      pa::is_act_vehicle(pa::VehicleId(node)) && pa::proto::decode(frame, m) == pa::proto::DecodeStatus::ok) {
    const pa::proto::TelemetryRates& r = m.telemetry_rates;
    vehicle_of(pa::VehicleId(node))
        .identification.telemetry(now_s, Eigen::Vector2d(r.rate_radps[0], r.rate_radps[1]),
                                  (r.saturation & 3u) != 0);
  }
  for (const link::ImpactReport& r : link_.take_impacts()) {
    if (impacts_.size() < kEventLogCapacity) impacts_.push_back(r);
    if (pa::is_act_vehicle(r.vehicle)) estimator_.report_impact(r.vehicle, r.t_s);
  }
}

// A vehicle that landed arms only from disarmed: its DISARM, once accepted, is followed by the ARM.
void GroundStation::tick(double now_s) {
  link_.tick(now_s);
  for (Vehicle& v : vehicles_) identify_motors(v, now_s);
  for (Vehicle& v : vehicles_) {
    if (!v.pending) continue;
    const link::CommandState s = link_.command_state(*v.pending);
    if (s == link::CommandState::pending) continue;
    v.pending.reset();
    if (s != link::CommandState::accepted) {
      v.command_failed = true;
      v.arm_after_disarm = false;
    } else if (v.arm_after_disarm) {
      v.arm_after_disarm = false;
      if (v.sequencer.task() == Task::arming)
        v.pending = link_.send_command(v.id, pa::proto::CommandCode::arm, 0, now_s);
    }
  }
}

mission::ConditionFacts GroundStation::facts(const Vehicle& v, double now_s) const {
  mission::ConditionFacts f;
  f.requests = v.requests;
  const link::VehicleLinkStatus& status = link_.status(v.id);
  f.link_up = !status.lost && (status.flags & pa::proto::kFlagGroundHeartbeatOk) != 0;
  f.armed = status.armed;
  f.on_ground = status.mode == pa::proto::Mode::disarmed || status.mode == pa::proto::Mode::landed ||
                status.mode == pa::proto::Mode::killed;
  f.command_failed = v.command_failed;
  f.task = v.sequencer.task();
  f.in_task_s = now_s - v.sequencer.task_since_s();
  f.estimated = estimator_.vehicle_initialised(v.id);
  f.since_pose_s = now_s - v.last_pose_s;
  f.target_m = v.target_m;
  if (f.estimated) {
    const estimation::VehicleEstimate e = estimator_.vehicle(v.id);
    f.position_m = e.state.p_m;
    f.velocity_mps = e.state.v_mps;
  }
  const bool holding = f.task == Task::throwing || f.task == Task::rebalance || f.task == Task::balance;
  if (holding && last_pole_pose_ && f.estimated)
    f.pole_end_from_plate_m = pole_end_from_plate_m(*last_pole_pose_, estimator_.plate(v.id).p_m,
                                                    estimator_.pole_model().half_length_m);
  const estimation::PoleEstimate pole = estimator_.pole();
  if (pole.valid) {
    f.pole_estimated_on_self = estimator_.mode() == estimation::on_vehicle_mode(v.id);
    if (f.pole_estimated_on_self) f.pole_tilt_rad = tilt_rad(pole.state);
    f.pole_estimated_free = estimator_.mode() == estimation::PoleMode::free;
  }
  // The pole on the floor ends an attempt's flight (before the launch it may lie there waiting
  // to be put on the thrower).
  const bool in_flight = phase_ == AttemptPhase::flight || phase_ == AttemptPhase::balancing;
  f.pole_on_floor = in_flight && last_pole_seen_m_ && last_pole_seen_m_->z() < config_.pole_down_height_m;
  f.throw_duration_s = flown_throw().duration_s();
  f.catcher = request_.catch_it && v.id != request_.thrower && phase_ != AttemptPhase::idle;
  f.catch_due = (phase_ == AttemptPhase::throwing || phase_ == AttemptPhase::flight) && catch_.due(now_s);
  f.catch_unreachable = catch_.unreachable();
  f.catch_infeasible = catch_.infeasible();
  f.catch_missed = catch_.missed();
  if (balanced_since_s_) f.balanced_for_s = now_s - *balanced_since_s_;
  return f;
}

void GroundStation::enter(Vehicle& v, double now_s) {
  const Task task = v.sequencer.task();
  const bool estimated = estimator_.vehicle_initialised(v.id);
  const Eigen::Vector3d here = estimated ? estimator_.vehicle(v.id).state.p_m : v.target_m;
  v.integral.setZero();
  v.set_point.velocity_mps.setZero();
  // Hold where the vehicle is now.
  const auto hold_here = [&] {
    v.set_point.position_m = here;
    v.set_point.valid = true;
  };
  switch (task) {
    case Task::parked:
    case Task::failsafe: v.set_point.valid = false; break;
    case Task::arming: {
      v.requests &= ~c::request_take_off;
      v.command_failed = false;
      // A vehicle that landed (on command or in its failsafe) arms only from disarmed.
      v.arm_after_disarm = link_.status(v.id).mode == pa::proto::Mode::landed;
      v.pending = link_.send_command(
          v.id, v.arm_after_disarm ? pa::proto::CommandCode::disarm : pa::proto::CommandCode::arm, 0, now_s);
      if (const std::optional<double> lag_s = identifications_.lag_at_arming(v.id))
        set_motor_lag(v, *lag_s, now_s);
      break;
    }
    case Task::take_off:
      v.take_off_ramp_mps2 = 0.0;
      v.target_m = Eigen::Vector3d(here.x(), here.y(), config_.take_off_height_m);
      hold_here();
      break;
    case Task::hover:
      if (!v.set_point.valid) hold_here();
      if (config_.identify_motors && v.sequencer.last_reason() == mission::Reason::airborne)
        v.identification.start(now_s, v.equalised_s);
      break;
    case Task::balance:
      balanced_since_s_.reset();
      if (!v.set_point.valid) v.set_point.position_m = here;
      v.set_point.valid = true;
      break;
    case Task::throwing: {
      v.requests &= ~c::request_throw;
      // Where on the plate the pole rests as the throw starts (see the throwing task's control).
      resting_offset_m_.setZero();
      if (estimated && estimator_.pole().valid) {
        const estimation::PlateKinematics plate = estimator_.plate(v.id);
        resting_offset_m_ =
            resting_pivot(plate, estimator_.pole().state, estimator_.pole_model().half_length_m).p_m -
            plate.p_m;
      }
      break;
    }
    case Task::release: v.requests &= ~c::request_abort; break;
    case Task::retreat:
      v.target_m = throw_origin_target();
      hold_here();
      break;
    case Task::wait: break;
    case Task::catching: {
      current_.catch_start_s = now_s;
      const double window_s = catch_.start(now_s, catch_height(), config_.catch_window_margin_s);
      // EXPECT_CATCH carries the window in milliseconds, 0.1-10 s (the firmware's bounds).
      v.pending =
          link_.send_command(v.id, pa::proto::CommandCode::expect_catch,
                             static_cast<std::int32_t>(std::clamp(window_s, 0.1, 10.0) * 1000.0), now_s);
      break;
    }
    case Task::rebalance:
      // The ground station flies the caught pole from here: end the firmware's own reaction.
      v.pending = link_.send_command(v.id, pa::proto::CommandCode::catch_handled, 0, now_s);
      v.target_m = here;
      hold_here();
      if (!current_.impact_s) {
        current_.impact_s = now_s;
        current_.catcher_at_impact_m = here;
        measure_impact_energy(v);
      }
      break;
    case Task::clear: {
      v.requests &= ~(c::request_abort | c::request_catch);
      // Sideways, away from where the pole comes down, at the same height.
      Eigen::Vector2d away = here.head<2>() - catch_.target_xy_m();
      if (away.norm() < 0.1) away = Eigen::Vector2d(0.0, 1.0);
      v.target_m.head<2>() = here.head<2>() + config_.clear_distance_m * away.normalized();
      v.target_m.z() = here.z();
      hold_here();
      break;
    }
    case Task::landing:
      v.requests &= ~c::request_land;
      v.pending = link_.send_command(v.id, pa::proto::CommandCode::land, 0, now_s);
      break;
  }
  // Whatever ended the throw and the catch is the attempt's account of them.
  if (phase_ != AttemptPhase::idle && v.id == request_.thrower && task == Task::release &&
      current_.thrower_end == mission::Reason::none)
    current_.thrower_end = v.sequencer.last_reason();
  if (request_.catch_it && v.id != request_.thrower &&
      (task == Task::clear || task == Task::rebalance || (task == Task::hover && current_.catch_start_s)) &&
      current_.catcher_end == mission::Reason::none) {
    current_.catcher_end = v.sequencer.last_reason();
  }
}

void GroundStation::integrate(Vehicle& v, const estimation::VehicleEstimate& e, double dt_s) {
  control::integrate_position_error(v.integral, v.set_point, v.target_m, e.state.p_m, dt_s,
                                    config_.position_integral_limit_ms);
}

// The integral shifts the LQR's reference position (p_ref = set point + k_i int e): a constant
// force offset then leaves no position error, whatever the controller (hover or balancing).
model::VehicleInput GroundStation::hover(Vehicle& v, const estimation::VehicleEstimate& e, double dt_s,
                                         bool integrate_error) {
  if (integrate_error) integrate(v, e, dt_s);
  control::HoverReference reference;
  reference.position_m = v.set_point.position_m + config_.position_integral_gain * v.integral;
  reference.velocity_mps = v.set_point.velocity_mps;
  return control::hover_law(hover_, e.state, reference);
}

std::optional<model::VehicleInput> GroundStation::control(Vehicle& v, double now_s, double dt_s) {
  const Task task = v.sequencer.task();
  if (task == Task::landing || task == Task::failsafe) return std::nullopt;
  if (task == Task::parked || task == Task::arming) {
    model::VehicleInput idle;
    idle.a_q_mps2 = 0.0;  // ARM needs a zero-thrust setpoint (fw/supervisor.hpp)
    return idle;
  }
  if (!estimator_.vehicle_initialised(v.id)) return std::nullopt;
  // Latency compensation: the state when this command acts.
  const double t_act = std::max(estimator_.time(), now_s + config_.command_lead_s);
  const estimation::VehicleEstimate e = ahead_->vehicle(v.id);
  const estimation::PoleEstimate pole = ahead_->pole();
  const estimation::PlateKinematics plate = ahead_->plate(v.id);
  const double L = ahead_->pole_model().half_length_m;
  const Eigen::Vector3d plate_offset = pa::kPlateHeightAboveCg_m * Eigen::Vector3d::UnitZ();
  const auto clamped = [&](const model::VehicleInput& u) { return control::clamp_input(u, config_.limits); };

  switch (task) {
    case Task::take_off:
    case Task::hover:
    case Task::wait:
    case Task::retreat:
    case Task::clear:
    case Task::rebalance: {
      if (task == Task::wait) v.target_m = waiting_target();
      control::move_set_point(v.set_point, v.target_m, e.state.p_m, dt_s, config_.carrot);
      const bool on_floor = task == Task::take_off && e.state.p_m.z() <= config_.take_off_integral_height_m;
      model::VehicleInput u = hover(v, e, dt_s, !on_floor);
      if (task == Task::rebalance) u.a_q_mps2 += config_.pole_weight_mps2;
      if (task == Task::take_off) {
        // The ramp grows on the floor and gives way in the air to the integral and the measured
        // thrust gain, which take over from it within a second.
        const bool stuck = on_floor && now_s - v.sequencer.task_since_s() > config_.take_off_ramp_after_s;
        v.take_off_ramp_mps2 =
            std::clamp(v.take_off_ramp_mps2 + (stuck ? 1.0 : -1.0) * config_.take_off_ramp_mps3 * dt_s, 0.0,
                       config_.limits.a_q_max_mps2);
        u.a_q_mps2 += v.take_off_ramp_mps2;
      }
      return clamped(u);
    }
    case Task::balance: {
      control::move_set_point(v.set_point, v.target_m, e.state.p_m, dt_s, config_.carrot);
      if (pole.valid && tilt_rad(pole.state) < config_.balance_settled_rad) {
        if (!balanced_since_s_) balanced_since_s_ = now_s;
      } else {
        balanced_since_s_.reset();
      }
      integrate(v, e, dt_s);
      return clamped(control::limit_tilt(
          control::balance_law(
              balancing_, resting_pivot(plate, pole.state, L), e.state, pole.state, L,
              v.set_point.position_m + plate_offset + config_.position_integral_gain * v.integral,
              v.set_point.velocity_mps, config_.pole_weight_mps2),
          e.state, config_.balance_tilt_limit));
    }
    case Task::throwing: {
      const double duration_s = flown_throw().duration_s();
      const double tau = std::min(t_act - v.sequencer.task_since_s(), duration_s);
      // The learnt throw (throw_learning.hpp) is the Fig. 5 throw's only: a throw to a target is
      // planned anew each time. Across the plane the pole is balanced about the end it rested on
      // as the throw started: about the plate's centre, passes drifted sideways from throw to
      // throw until one was dropped (hil fly --passes 100 --randomise, seeds 1 and 4: 37 and 7
      // passes, then 84 and 92); taken as the throw starts, since the filter's estimate of it
      // moves while the throw accelerates (the learnt throw's error grew, throw_learning_test).
      const model::PlanarState<double> shift =
          target_throw_ ? model::PlanarState<double>::Zero()
                        : adaptation::reference_shift(learner_.throw_correction(), tau, duration_s);
      const planning::ThrowStep step = planning::throw_step(
          flown_tracker(), balancing_, tau, frame_, control::Pivot{plate.p_m, plate.v_mps}, resting_offset_m_,
          e.state, pole.state, L, shift, config_.limits);
      if (tau >= duration_s - config_.launch_state_window_s) throw_end_ = ThrowEnd{tau, step.state};
      return clamped(step.input);
    }
    case Task::release: {
      const Eigen::Vector3d pitch_back = frame_.body_rates_to_vehicle(
          Eigen::Vector3d(0.0, flown_throw().input.back()(model::planar::kPitchRate), 0.0));
      return clamped(control::release_law(e.state, t_act - v.sequencer.task_since_s(),
                                          config_.release_pitch_s, pitch_back,
                                          config_.release_level_gain_per_s, config_.limits.a_q_min_mps2));
    }
    case Task::catching: {
      if (!catch_.trajectory()) return clamped(hover(v, e, dt_s, false));
      const planning::CatchReference ref = catch_.trajectory()->reference(t_act - catch_.start_s());
      // The hover LQR about the reference's state with its nominal inputs (46), (47) as feed
      // forward: a time-varying reference tracked with the hover gains, which hold across the
      // manoeuvre's tilts (at most atan(a_max / g) ~ 23 degrees plus the xy correction's). The
      // integral learnt while waiting stays in force, frozen.
      control::HoverReference reference;
      reference.position_m = ref.position_m + config_.position_integral_gain * v.integral;
      reference.velocity_mps = ref.velocity_mps;
      reference.roll_rad = ref.roll_rad;
      reference.pitch_rad = ref.pitch_rad;
      reference.yaw_rad = ref.yaw_rad;
      reference.thrust_mps2 = ref.thrust_mps2;
      reference.body_rates_radps = ref.body_rates_radps;
      v.set_point.position_m = ref.position_m;
      return clamped(control::hover_law(hover_, e.state, reference));
    }
    default: return std::nullopt;
  }
}

void GroundStation::on_mocap(const estimation::MocapFrame& frame, double now_s) {
  const double dt_s = last_mocap_s_ > -1e8 ? std::clamp(now_s - last_mocap_s_, 0.0, 0.05) : 0.005;
  last_mocap_s_ = now_s;
  estimator_.update(frame);
  for (Vehicle& v : vehicles_) {
    const std::optional<estimation::MocapPose>& pose = frame.vehicle[pa::act_slot(v.id)];
    if (!pose) continue;
    v.last_pose_s = now_s;
    measure_thrust_gain(v, now_s, *pose);
  }
  if (frame.pole) {
    last_pole_seen_m_ = frame.pole->p_m;
    last_pole_pose_ = *frame.pole;
  }
  // The estimator predicted, states only, to when the commands act (latency compensation).
  ahead_.emplace(estimator_.predicted(std::max(estimator_.time(), now_s + config_.command_lead_s)));

  update_attempt(now_s);
  for (Vehicle& v : vehicles_) {
    const Task before = v.sequencer.task();
    if (v.sequencer.step(mission::condition_word(facts(v, now_s), config_.conditions), now_s)) {
      if (events_.size() < kEventLogCapacity)
        events_.push_back({now_s, v.id, before, v.sequencer.task(), v.sequencer.last_reason()});
      enter(v, now_s);
    }
    const std::optional<model::VehicleInput> u = control(v, now_s, dt_s);
    if (u) send(v, *u, now_s);
  }
}

// The thrust gain is measured while the vehicle flies on its thrust alone: not on the floor, not
// throwing, releasing, catching or with a pole swinging up; balancing, the pole's weight is the
// known extra load. Poses are stamped with the ground clock on arrival, the clock the commands
// are stamped with: the motion capture's own may be another (a plant slower than real time, an
// arena's system), and its latency only shifts the window by tens of milliseconds of steady flight.
void GroundStation::measure_thrust_gain(Vehicle& v, double t_s, const estimation::MocapPose& pose) {
  const Task task = v.sequencer.task();
  const bool steady = task == Task::take_off || task == Task::hover || task == Task::wait ||
                      task == Task::retreat || task == Task::clear || task == Task::balance;
  const double load = task == Task::balance ? config_.pole_weight_mps2 : 0.0;
  v.thrust_gain.pose(t_s, pose.p_m.z(), (pose.q * Eigen::Vector3d::UnitZ()).z(), load,
                     steady && pose.p_m.z() > config_.thrust_gain_min_height_m);
}

// The setpoint carries a_q / k (the vehicle delivers k a_q); the estimator's model is told what
// the vehicle delivers, the thrust-gain estimator what it was commanded.
void GroundStation::send(Vehicle& v, model::VehicleInput u, double now_s) {
  const double gain = config_.compensate_thrust_gain ? v.thrust_gain.gain() : 1.0;
  // The laws ask within a_q's limits of the vehicle as built; the setpoint asks its motors for it,
  // up to their full thrust.
  if (u.a_q_mps2 > 0.0)
    u.a_q_mps2 =
        std::clamp(std::clamp(u.a_q_mps2, config_.limits.a_q_min_mps2, config_.limits.a_q_max_mps2) / gain,
                   config_.limits.a_q_min_mps2, config_.airframe_thrust_max_mps2);
  u.omega_radps.head<2>() += v.identification.excitation(now_s);
  model::VehicleInput sent = link_.send_setpoint(v.id, u);
  v.identification.command_sent(now_s, sent.omega_radps.head<2>());
  const double t_acts_s = now_s + config_.command_lead_s;
  v.thrust_gain.command(t_acts_s, sent.a_q_mps2);
  sent.a_q_mps2 *= gain;
  estimator_.set_command(v.id, t_acts_s, sent);
}

// The identification flight's fit once it is over, recorded; a lag that differs from the
// equaliser's by more than the fit's accuracy goes on board. A refused fit keeps what is set.
void GroundStation::identify_motors(Vehicle& v, double now_s) {
  if (v.equaliser_command) {
    const link::CommandState s = link_.command_state(*v.equaliser_command);
    if (s != link::CommandState::pending) {
      if (s == link::CommandState::accepted) v.equalised_s = v.equaliser_sent_s;
      v.equaliser_command.reset();
    }
  }
  const std::optional<estimation::IdentificationResult> result = v.identification.finish(now_s);
  if (!result) return;
  v.identified = result;
  const std::optional<double> k =
      v.thrust_gain.measurements() > 0 ? std::optional(v.thrust_gain.gain()) : std::nullopt;
  if (const std::optional<double> lag_s = identifications_.finished(v.id, *result, k, now_s, v.equalised_s))
    set_motor_lag(v, *lag_s, now_s);
}

void GroundStation::set_motor_lag(Vehicle& v, double lag_s, double now_s) {
  v.equaliser_sent_s = lag_s;
  v.equaliser_command = link_.send_command(v.id, pa::proto::CommandCode::set_motor_time_constant,
                                           static_cast<std::int32_t>(std::lround(lag_s * 1e6)), now_s);
}

std::vector<link::ImpactReport> GroundStation::take_impacts() {
  std::vector<link::ImpactReport> out;
  out.swap(impacts_);
  return out;
}

std::vector<MissionEvent> GroundStation::take_events() {
  std::vector<MissionEvent> out;
  out.swap(events_);
  return out;
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

void GroundStation::update_attempt(double now_s) {
  if (phase_ == AttemptPhase::idle) return;
  Vehicle& thrower = vehicle_of(request_.thrower);
  Vehicle& catcher = other(thrower);
  const estimation::PoleEstimate pole = estimator_.pole();

  if (thrower.sequencer.task() == Task::balance && thrower.set_point.valid)
    thrower.target_m = throw_origin_target();
  // A catcher lost (no heartbeat, no pose) before the catch is in its failsafe: the catch is off.
  // Before the throw the attempt ends there (the thrower keeps balancing the pole); once thrown,
  // the pole comes down and ends it.
  if (request_.catch_it && catcher.sequencer.task() == Task::failsafe && !current_.impact_s &&
      current_.catcher_end == mission::Reason::none) {
    current_.catcher_end = catcher.sequencer.last_reason();
    if (phase_ == AttemptPhase::preparing) {
      end_attempt(now_s);
      return;
    }
  }
  switch (phase_) {
    case AttemptPhase::preparing: {
      const bool catcher_ready = !request_.catch_it || (catcher.sequencer.task() == Task::wait &&
                                                        (catcher.sequencer.last_conditions() & c::at_target));
      const bool thrower_at_origin = (thrower.sequencer.last_conditions() & c::at_target) != 0;
      if (catcher_ready && thrower_at_origin) thrower.requests |= c::request_throw;
      if (thrower.sequencer.task() == Task::throwing) {
        phase_ = AttemptPhase::throwing;
        current_.throw_start_s = thrower.sequencer.task_since_s();
        current_.waiting_xy_m = waiting_xy() + request_.catch_offset_m;
        current_.catch_height_m = catch_height();
        const double catch_instant_s =
            target_throw_ ? target_throw_->plan.catching_instant.t_s : learner_.catch_instant_s();
        catch_.plan(current_, current_.throw_start_s + flown_throw().duration_s() + config_.launch_delay_s,
                    catch_instant_s);
      }
      break;
    }
    case AttemptPhase::throwing: {
      // The launch: the estimator's switch to free flight after the throw's manoeuvre began.
      const std::optional<estimation::ModeSwitch> s = estimator_.last_switch();
      // Only a call at the end of the throw (see the conditions on the flip-flops during it).
      if (s && s->to == estimation::PoleMode::free &&
          s->event_t_s > current_.throw_start_s + flown_throw().duration_s() - config_.launch_call_window_s) {
        current_.launch_s = s->event_t_s;
        phase_ = AttemptPhase::flight;
      } else if (thrower.sequencer.task() != Task::throwing && thrower.sequencer.task() != Task::release &&
                 !current_.launch_s) {
        end_attempt(now_s);  // the throw was abandoned (aborted or the pole fell)
        return;
      }
      break;
    }
    default: break;
  }
  // The catch manoeuvre starts before the launch (T_z ~ 1.8 s against ~1.1 s of flight): plan
  // it from the throw's start on, from the waiting point until the pole flies.
  if (phase_ == AttemptPhase::flight) catch_.retime(now_s, catch_view(catcher), current_);
  if (request_.catch_it && phase_ != AttemptPhase::preparing)
    catch_.update(now_s, catch_view(catcher), current_);
  if (phase_ == AttemptPhase::flight || phase_ == AttemptPhase::balancing) {
    // The pole's free flight, from the launch to the impact, for the evaluation of (42).
    if (pole.valid && pole.mode == estimation::PoleMode::free && current_.launch_s && !current_.impact_s &&
        (flight_.empty() || pole.t_s > flight_.back().t_s))
      flight_.push_back({pole.t_s, pole.state});
    // The ends of an attempt.
    if (catcher.sequencer.task() == Task::balance) {
      phase_ = AttemptPhase::balancing;
      if (!balanced_on_catcher_s_) balanced_on_catcher_s_ = now_s;
      if (now_s - *balanced_on_catcher_s_ >= config_.caught_after_s) {
        current_.caught = true;
        end_attempt(now_s);
        return;
      }
    } else {
      balanced_on_catcher_s_.reset();
    }
    const bool down = last_pole_seen_m_ && last_pole_seen_m_->z() < config_.pole_down_height_m;
    if (down || now_s - current_.throw_start_s > config_.attempt_timeout_s) {
      end_attempt(now_s);
      return;
    }
  }
}

void GroundStation::end_attempt(double now_s) {
  Vehicle& thrower = vehicle_of(request_.thrower);
  Vehicle& catcher = other(thrower);
  catcher.requests &= ~c::request_catch;
  thrower.requests &= ~c::request_throw;
  if (current_.launch_s && flight_.size() >= 2)
    current_.optimal =
        adaptation::evaluate_optimal_catch(flight_, *current_.launch_s, estimator_.pole_model());
  if (current_.launch_s && throw_end_) {
    // The state tracked last, carried to T along the plan (a few milliseconds of it).
    const planning::ThrowTrajectory& plan = flown_throw();
    const double T = plan.duration_s();
    const model::PlanarState<double> at_t =
        throw_end_->state + plan.state_at(T) - plan.state_at(throw_end_->tau_s);
    current_.launch_flown = adaptation::launch_state_of(at_t);
    current_.launch_error = adaptation::launch_vector(*current_.launch_flown) -
                            adaptation::launch_vector(adaptation::launch_state_of(plan.state_at(T)));
    if (!target_throw_) learner_.learn_launch(*current_.launch_flown);
  }
  adaptation::ThrowRecord record = record_of(request_, current_, frame_, catch_.target_xy_m(), now_s);
  // The optimal catch evaluated after the throw counts only if it agrees with the one predicted
  // in flight (adaptation/learner.hpp).
  const bool agrees =
      current_.optimal && learner_.evaluation_agrees(current_.optimal->point, current_.predicted_optimal);
  if (target_throw_) {
    // A throw to a target is not the Fig. 5 throw whose catch the adaptation learns (its catch
    // point, height and instant are its plan's): its miss is learnt, the record kept, neither
    // adapted nor stored.
    if (agrees) {
      const adaptation::OptimalCatch& o = current_.optimal->point;
      const Eigen::Vector3d came_down(o.xy_m.x(), o.xy_m.y(), o.height_m);
      learner_.learn_target_miss(frame_.to_frame(came_down) - frame_.to_frame(target_throw_->plan.target_m));
    }
    record.note = "a throw to a target: not adapted";
    learner_.keep(record);
  } else {
    if (current_.optimal) {
      adaptation::OptimalCatch o = current_.optimal->point;
      o.height_m -= frame_.origin_m.z();
      o.xy_m = frame_.to_frame_xy(o.xy_m);
      learner_.learn_optimal_catch(record, o, agrees);
    }
    learner_.adapt(record);
  }
  reports_.push_back(current_);
  phase_ = AttemptPhase::idle;
  catch_.reset();
  // Back to the start: the thrower to the throw's origin, the catcher to the next waiting point.
  thrower.target_m = throw_origin_target();
  catcher.target_m = waiting_target();
}

}  // namespace gs::runtime
