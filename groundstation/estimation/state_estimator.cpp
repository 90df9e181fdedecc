#include "groundstation/estimation/state_estimator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace gs::estimation {
namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kTimeEps_s = 1e-9;
constexpr double kVehicleNisGate = 16.81;  // chi-square 99 %, 6 dof
constexpr double kPoleNisGate = 15.09;     // chi-square 99 %, 5 dof

PlateKinematics interpolate(const PlateKinematics& a, const PlateKinematics& b, double frac) {
  PlateKinematics k = b;
  k.p_m = a.p_m + frac * (b.p_m - a.p_m);
  k.v_mps = a.v_mps + frac * (b.v_mps - a.v_mps);
  k.a_mps2 = a.a_mps2 + frac * (b.a_mps2 - a.a_mps2);
  k.inertial_from_body = frac < 0.5 ? a.inertial_from_body : b.inertial_from_body;
  return k;
}

// The slot (0, 1) of the vehicle the pole rests on in `mode`, -1 in free flight.
int slot_of_mode(PoleMode mode) {
  const std::optional<pa::VehicleId> v = vehicle_of_mode(mode);
  return v ? static_cast<int>(pa::act_slot(*v)) : -1;
}

PoleLengthParams with_nominal(PoleLengthParams params, double nominal_m) {
  params.nominal_m = nominal_m;
  return params;
}

}  // namespace

std::string_view switch_reason_name(SwitchReason reason) {
  switch (reason) {
    case SwitchReason::initial: return "initial";
    case SwitchReason::contact_force: return "contact_force";
    case SwitchReason::plate_contact: return "plate_contact";
    case SwitchReason::impact_report: return "impact_report";
    case SwitchReason::innovation: return "innovation";
    case SwitchReason::filter_invalid: return "filter_invalid";
    case SwitchReason::reinitialised: return "reinitialised";
  }
  return "initial";
}

StateEstimator::StateEstimator(const StateEstimatorConfig& config)
    : config_(config),
      vehicles_{VehicleObserver(config.vehicle), VehicleObserver(config.vehicle)},
      impact_report_t_s_{kNan, kNan},
      free_(config.free_flight),
      on_{PoleOnVehicleEkf(config.on_vehicle), PoleOnVehicleEkf(config.on_vehicle)},
      selector_(config.selector),
      pole_length_(with_nominal(config.pole_length, config.on_vehicle.pole.half_length_m)),
      vehicle_health_{BodyHealthTracker(kVehicleNisGate), BodyHealthTracker(kVehicleNisGate)},
      pole_health_(kPoleNisGate) {}

// ---------------------------------------------------------------------------------------------
// Commands and impact reports

void StateEstimator::set_command(pa::VehicleId vehicle, double t_s, const model::VehicleInput& input) {
  if (!pa::is_act_vehicle(vehicle) || !std::isfinite(t_s) || !std::isfinite(input.a_q_mps2) ||
      !input.omega_radps.allFinite()) {
    return;
  }
  CommandQueue& q = commands_[pa::act_slot(vehicle)];
  if (q.count > 0) {
    TimedCommand& last = q.items[(q.head + q.count - 1) % kCommandQueueCapacity];
    if (t_s < last.t_s - kTimeEps_s) return;  // out of order: the newer command stands
    if (t_s <= last.t_s + kTimeEps_s) {
      last.input = input;
      return;
    }
  }
  if (q.count == kCommandQueueCapacity) {
    q.head = (q.head + 1) % kCommandQueueCapacity;
    --q.count;
  }
  q.items[(q.head + q.count) % kCommandQueueCapacity] = {t_s, input};
  ++q.count;
}

const model::VehicleInput* StateEstimator::command_at(int index, double t_s) const {
  const CommandQueue& q = commands_[index];
  const TimedCommand* found = nullptr;
  for (int i = 0; i < q.count; ++i) {
    const TimedCommand& c = q.at(i);
    if (c.t_s > t_s + kTimeEps_s) break;
    found = &c;
  }
  if (found == nullptr || t_s - found->t_s > config_.command_timeout_s) return nullptr;
  return &found->input;
}

double StateEstimator::next_command_change(double after_t_s, double until_t_s) const {
  double next = until_t_s;
  for (const CommandQueue& q : commands_) {
    for (int i = 0; i < q.count; ++i) {
      const double t = q.at(i).t_s;
      if (t > after_t_s + kTimeEps_s) {
        next = std::min(next, t);
        break;
      }
    }
  }
  return next;
}

void StateEstimator::drop_old_commands(double t_s) {
  for (CommandQueue& q : commands_) {
    while (q.count >= 2 && q.at(1).t_s <= t_s + kTimeEps_s) {
      q.head = (q.head + 1) % kCommandQueueCapacity;
      --q.count;
    }
  }
}

void StateEstimator::set_pole_measurement_sigma(pa::VehicleId vehicle, double position_m,
                                                double direction_rad) {
  if (!pa::is_act_vehicle(vehicle) || !(position_m > 0.0) || !(direction_rad > 0.0)) return;
  on_[pa::act_slot(vehicle)].set_measurement_sigma(position_m, direction_rad);
}

void StateEstimator::report_impact(pa::VehicleId vehicle, double t_s) {
  if (!pa::is_act_vehicle(vehicle) || !std::isfinite(t_s)) return;
  impact_report_t_s_[pa::act_slot(vehicle)] = t_s;
}

bool StateEstimator::impact_report_pending(int index) const {
  const double t = impact_report_t_s_[index];
  return std::isfinite(t) && t_s_ >= t - config_.max_step_s && t_s_ <= t + config_.impact_report_window_s;
}

// ---------------------------------------------------------------------------------------------
// Propagation

void StateEstimator::advance_to(double t_s) {
  pole_estimate_.reset();
  if (!std::isfinite(t_s)) return;
  if (!started_) {
    t_s_ = t_s;
    started_ = true;
    return;
  }
  if (t_s - t_s_ > config_.max_coast_s) {
    start_over(t_s);
    return;
  }
  const double max_step = config_.max_step_s > 0.0 ? config_.max_step_s : 0.005;
  if (!(t_s_ < t_s - kTimeEps_s)) return;
  std::optional<NormalForceEstimate> force_at_step;
  while (t_s_ < t_s - kTimeEps_s) {
    const double next = next_command_change(t_s_, std::min(t_s, t_s_ + max_step));
    step(next - t_s_, force_at_step);
    t_s_ = next;
    drop_old_commands(t_s_);
  }
  free_.predict(free_behind_s_, propagation_);
  free_behind_s_ = 0.0;
}

void StateEstimator::start_over(double t_s) {
  vehicles_ = {VehicleObserver(config_.vehicle), VehicleObserver(config_.vehicle)};
  pole_seen_ = false;  // the next pole pose initialises it (SwitchReason::initial)
  on_candidate_valid_ = {};
  impact_report_t_s_ = {kNan, kNan};
  pole_rejections_ = 0;
  free_behind_s_ = 0.0;
  t_s_ = t_s;
  drop_old_commands(t_s_);
  ++start_overs_;
}

void StateEstimator::step(double h, std::optional<NormalForceEstimate>& normal_force) {
  // The plates the pole's step reads: both in free flight (impacts), else only the active one's
  // (a vehicle's plate is kept until its state changes, so a step's start is the last one's end).
  const int active = slot_of_mode(selector_.active());
  const auto read = [&](int i) {
    return pole_seen_ && vehicles_[i].initialised() && (active < 0 || active == i);
  };
  std::array<PlateKinematics, 2> before;
  std::array<PlateKinematics, 2> after;
  for (int i = 0; i < 2; ++i) {
    if (read(i)) before[i] = vehicles_[i].plate();
  }
  for (int i = 0; i < 2; ++i) {
    if (!vehicles_[i].initialised()) continue;
    vehicles_[i].predict(h, command_at(i, t_s_), propagation_);
    if (read(i)) after[i] = vehicles_[i].plate();
  }
  if (pole_seen_) step_pole(h, before, after, normal_force);
}

void StateEstimator::step_pole(double h, const std::array<PlateKinematics, 2>& before,
                               const std::array<PlateKinematics, 2>& after,
                               std::optional<NormalForceEstimate>& normal_force) {
  const PoleMode active = selector_.active();
  const std::optional<NormalForceEstimate> carried = std::exchange(normal_force, std::nullopt);
  const model::PoleParams& params = config_.on_vehicle.pole;
  // A prediction (mean only, predicted()) is read for the active mode alone, and a switch inside
  // it seeds the new mode from the old: its candidates are not propagated (a third of its cost).
  const bool candidates = propagation_ == Propagation::mean_and_covariance;
  if (active == PoleMode::free) {
    const PoleFreeFlightEkf start = free_;
    free_.predict(h, propagation_);
    for (int i = 0; i < 2; ++i) {
      if (!vehicles_[i].initialised()) continue;
      // Impact: the lower end crossed the plate's plane inside the rim, closing on it.
      const PlateContactGeometry g0 = plate_contact_geometry(start.state(), before[i], params);
      const PlateContactGeometry g1 = plate_contact_geometry(free_.state(), after[i], params);
      if (!(g0.height_m > 0.0 && g1.height_m <= 0.0)) continue;
      const double frac = g0.height_m / (g0.height_m - g1.height_m);
      const double radial = g0.radial_m + frac * (g1.radial_m - g0.radial_m);
      const double approach = g0.approach_speed_mps + frac * (g1.approach_speed_mps - g0.approach_speed_mps);
      if (radial > config_.candidate_gate.plate_radius_m + config_.impact_radial_margin_m ||
          approach < config_.impact_min_approach_speed_mps) {
        continue;
      }
      free_ = start;
      free_.predict(frac * h, propagation_);
      const PlateKinematics plate = interpolate(before[i], after[i], frac);
      const OnVehicleSeed seed = on_vehicle_seed_after_impact(free_.state(), free_.pole_covariance(), plate,
                                                              params, config_.impact_rate_sigma_mps);
      on_[i].reset(seed.state, seed.covariance, seed.direction_sign);
      on_[i].predict((1.0 - frac) * h, after[i].a_mps2, propagation_);
      switch_to(on_vehicle_mode(pa::kActVehicles[i]), SwitchReason::plate_contact, t_s_ + frac * h, t_s_ + h);
      reseed_candidates();
      return;
    }
    for (int i = 0; i < 2 && candidates; ++i) {
      if (on_candidate_valid_[i]) on_[i].predict(h, 0.5 * (before[i].a_mps2 + after[i].a_mps2), propagation_);
    }
    return;
  }

  const int j = slot_of_mode(active);
  if (!vehicles_[j].initialised()) return;
  const PoleOnVehicleEkf start = on_[j];
  const NormalForceEstimate f0 = carried ? *carried : start.normal_force(before[j]);
  on_[j].predict(h, 0.5 * (before[j].a_mps2 + after[j].a_mps2), propagation_);
  const NormalForceEstimate f1 = on_[j].normal_force(after[j]);
  const double threshold = -(config_.launch_margin_mps2 + config_.launch_sigmas * f1.sigma_mps2);
  if (f1.value_mps2 < threshold || !on_[j].valid()) {
    // Launch: the pole is free from the instant F_N crossed zero (or the step's start).
    const bool lost_geometry = !on_[j].valid() && !(f1.value_mps2 < threshold);
    const double frac =
        f0.value_mps2 > 0.0 && f1.value_mps2 < 0.0 ? f0.value_mps2 / (f0.value_mps2 - f1.value_mps2) : 0.0;
    on_[j] = start;
    on_[j].predict(frac * h, 0.5 * (before[j].a_mps2 + after[j].a_mps2), propagation_);
    const PlateKinematics plate = interpolate(before[j], after[j], frac);
    FreeFlightSeed seed = free_flight_seed_from_on_vehicle(on_[j], plate);
    const double sw = config_.launch_rate_sigma_radps;
    seed.covariance.block<3, 3>(PoleFreeFlightEkf::kW, PoleFreeFlightEkf::kW) +=
        sw * sw * Eigen::Matrix3d::Identity();
    free_.reset(seed.state, seed.covariance, drag_scale_, config_.drag_scale_sigma);
    free_behind_s_ = 0.0;
    free_.predict((1.0 - frac) * h, propagation_);
    switch_to(PoleMode::free, lost_geometry ? SwitchReason::filter_invalid : SwitchReason::contact_force,
              t_s_ + frac * h, t_s_ + h);
    launched_from_ = j;
    launch_t_s_ = t_s_ + frac * h;
    reseed_candidates();
    return;
  }
  normal_force = f1;  // the next step's start, in this mode on this plate
  // The free-flight candidate does not depend on the commands or the plates: it is propagated
  // once at the end of advance_to() instead of in each command step (3.6 a frame, each a 13 x 13
  // covariance step), no step longer than its max_step_s.
  if (candidates) free_behind_s_ += h;
}

// ---------------------------------------------------------------------------------------------
// Mode bookkeeping

void StateEstimator::switch_to(PoleMode mode, SwitchReason reason, double event_t_s, double detected_t_s) {
  const PoleMode from = selector_.active();
  // The drag scale learnt in a flight that ended on a plate seeds the next launch, if the flight
  // taught it something (a pole sliding on the floor teaches nothing about drag).
  const bool caught = reason == SwitchReason::plate_contact || reason == SwitchReason::impact_report;
  if (from == PoleMode::free && caught && config_.carry_drag_scale &&
      config_.free_flight.estimate_drag_scale) {
    const double sigma =
        std::sqrt(std::max(0.0, free_.covariance()(PoleFreeFlightEkf::kK, PoleFreeFlightEkf::kK)));
    if (sigma < 0.5 * config_.drag_scale_sigma) drag_scale_ = free_.drag_scale();
  }
  selector_.reset(mode);
  ModeSwitch s;
  s.event_t_s = event_t_s;
  s.detected_t_s = detected_t_s;
  s.from = from;
  s.to = mode;
  s.reason = reason;
  switch_log_[switch_count_ % kSwitchLogCapacity] = s;
  ++switch_count_;
  ++switch_count_by_reason_[static_cast<int>(reason)];
  mode_since_s_ = event_t_s;
  last_switch_detected_s_ = detected_t_s;
  if (mode != PoleMode::free) impact_report_t_s_[slot_of_mode(mode)] = kNan;
}

void StateEstimator::reseed_candidates() {
  const PoleMode active = selector_.active();
  if (active == PoleMode::free) {
    for (int i = 0; i < 2; ++i) {
      const PoleMode m = on_vehicle_mode(pa::kActVehicles[i]);
      if (!vehicles_[i].initialised()) {
        on_candidate_valid_[i] = false;
        continue;
      }
      if (on_candidate_valid_[i] && selector_.accumulating(m) && on_[i].valid()) continue;
      const std::optional<OnVehicleSeed> seed =
          on_vehicle_seed_from_free_flight(free_.state(), free_.pole_covariance(), vehicles_[i].plate(),
                                           config_.on_vehicle.pole, config_.candidate_gate);
      on_candidate_valid_[i] = false;
      if (seed) {
        on_[i].reset(seed->state, seed->covariance, seed->direction_sign);
        on_candidate_valid_[i] = on_[i].valid();
      }
    }
    return;
  }
  const int j = slot_of_mode(active);
  on_candidate_valid_ = {false, false};
  if (!free_candidate_reseeded()) return;
  const FreeFlightSeed seed = free_flight_seed_from_on_vehicle(on_[j], vehicles_[j].plate());
  free_.reset(seed.state, seed.covariance, drag_scale_, config_.drag_scale_sigma);
}

bool StateEstimator::free_candidate_reseeded() const {
  const int j = slot_of_mode(selector_.active());
  return j >= 0 && vehicles_[j].initialised() && !selector_.accumulating(PoleMode::free);
}

// ---------------------------------------------------------------------------------------------
// Measurements

void StateEstimator::update(const MocapFrame& frame) {
  pole_estimate_.reset();
  if (!std::isfinite(frame.t_s)) return;
  if (started_ && frame.t_s < t_s_ - kTimeEps_s) {
    ++frames_out_of_order_;
    return;
  }
  advance_to(frame.t_s);
  ++frames_;
  for (int i = 0; i < 2; ++i) {
    if (!frame.vehicle[i]) continue;
    vehicle_health_[i].sample(frame.t_s);
    const VehicleUpdateResult r = vehicles_[i].update(*frame.vehicle[i]);
    if (!r.accepted) {
      vehicle_health_[i].rejected();
    } else if (!r.reinitialised) {
      vehicle_health_[i].innovation(r.nis);
    }
  }
  if (!frame.pole) return;
  pole_health_.sample(frame.t_s);
  if (!is_usable_pose(*frame.pole)) {
    pole_health_.rejected();
    return;
  }
  const PoleMeasurement m{frame.pole->p_m, pole_direction_from_quaternion(frame.pole->q)};
  if (!pole_seen_) {
    initialise_pole(m, SwitchReason::initial);
  } else {
    update_pole(m);
  }
  if (config_.learn_pole_length) learn_pole_length(frame);
}

void StateEstimator::learn_pole_length(const MocapFrame& frame) {
  const int i = slot_of_mode(selector_.active());
  if (i < 0 || !frame.vehicle[i]) return;
  const std::optional<double> sample = pole_half_length_sample(
      *frame.vehicle[i], *frame.pole, config_.vehicle.plate_height_m, config_.pole_length);
  if (!sample || !pole_length_.add(*sample)) return;
  const std::optional<double> length = pole_length_.estimate();
  // A tenth of a millimetre changes nothing the filters could tell; skip the copies.
  if (!length || std::abs(*length - config_.on_vehicle.pole.half_length_m) < 1e-4) return;
  config_.on_vehicle.pole.half_length_m = *length;
  config_.free_flight.pole.half_length_m = *length;
  free_.set_pole_half_length(*length);
  for (PoleOnVehicleEkf& filter : on_) filter.set_pole_half_length(*length);
}

void StateEstimator::initialise_pole(const PoleMeasurement& m, SwitchReason reason) {
  model::PoleState s;
  s.p_m = m.p_m;
  s.n = m.n;
  PoleCovariance p = PoleCovariance::Zero();
  const double sp = config_.free_flight.mocap_position_sigma_m;
  const double sn = config_.free_flight.mocap_direction_sigma_rad;
  const double sv = config_.initial_velocity_sigma_mps;
  const double sw = config_.initial_rate_sigma_radps;
  p.diagonal() << sp * sp, sp * sp, sp * sp, sv * sv, sv * sv, sv * sv, sn * sn, sn * sn, sn * sn, sw * sw,
      sw * sw, sw * sw;
  free_.reset(s, p, drag_scale_, config_.drag_scale_sigma);
  pole_seen_ = true;
  PoleMode mode = PoleMode::free;
  for (int i = 0; i < 2 && mode == PoleMode::free; ++i) {
    if (!vehicles_[i].initialised()) continue;
    // At rest relative to the vehicle, if it rests on it.
    model::PoleState rel = s;
    rel.v_mps = vehicles_[i].plate().v_mps;
    const std::optional<OnVehicleSeed> seed = on_vehicle_seed_from_free_flight(
        rel, free_.pole_covariance(), vehicles_[i].plate(), config_.on_vehicle.pole, config_.candidate_gate);
    if (!seed) continue;
    on_[i].reset(seed->state, seed->covariance, seed->direction_sign);
    if (on_[i].valid()) mode = on_vehicle_mode(pa::kActVehicles[i]);
  }
  switch_to(mode, reason, t_s_, t_s_);
  reseed_candidates();
  pole_rejections_ = 0;
}

void StateEstimator::update_pole(const PoleMeasurement& m) {
  const model::PoleParams& params = config_.on_vehicle.pole;
  std::array<PlateKinematics, 2> plates;
  for (int i = 0; i < 2; ++i) {
    if (vehicles_[i].initialised()) plates[i] = vehicles_[i].plate();
  }

  // An impact reported by a vehicle, with the MEASURED pole's lower end at its plate: switch at
  // once. The report arrives over the radio after the impact, when the free-flight filter has
  // already been pulled by a few frames of a pole that stopped, so the geometry comes from the
  // measurement and only the rates (through the impact map, with its uncertainty) from the
  // free-flight estimate.
  if (selector_.active() == PoleMode::free) {
    model::PoleState measured = free_.state();
    measured.p_m = m.p_m;
    measured.n = m.n;
    measured = model::normalised_pole_state(measured);
    for (int i = 0; i < 2; ++i) {
      if (!impact_report_pending(i) || !vehicles_[i].initialised()) continue;
      const PlateContactGeometry g = plate_contact_geometry(measured, plates[i], params);
      const PlateContactGate& gate = config_.impact_report_gate;
      if (g.radial_m > gate.plate_radius_m + gate.radial_margin_m ||
          std::abs(g.height_m) > gate.height_margin_m) {
        continue;
      }
      const OnVehicleSeed seed = on_vehicle_seed_after_impact(measured, free_.pole_covariance(), plates[i],
                                                              params, config_.impact_rate_sigma_mps);
      on_[i].reset(seed.state, seed.covariance, seed.direction_sign);
      if (!on_[i].valid()) continue;
      switch_to(on_vehicle_mode(pa::kActVehicles[i]), SwitchReason::impact_report, impact_report_t_s_[i],
                t_s_);
      reseed_candidates();
      break;
    }
  }
  // The active on-vehicle filter lost its geometry: the pole is no longer on the plate.
  if (const int v = slot_of_mode(selector_.active()); v >= 0 && !on_[v].valid()) {
    const FreeFlightSeed seed = free_flight_seed_from_on_vehicle(on_[v], plates[v]);
    free_.reset(seed.state, seed.covariance, drag_scale_, config_.drag_scale_sigma);
    switch_to(PoleMode::free, SwitchReason::filter_invalid, t_s_, t_s_);
    reseed_candidates();
  }

  const PoleMode active = selector_.active();
  std::array<bool, kPoleModeCount> evaluated{};
  evaluated[mode_index(PoleMode::free)] = true;  // active, or the candidate of an on-vehicle mode
  for (int i = 0; i < 2; ++i) {
    const PoleMode mi = on_vehicle_mode(pa::kActVehicles[i]);
    evaluated[mode_index(mi)] =
        active == mi || (active == PoleMode::free && on_candidate_valid_[i] && on_[i].valid());
  }
  std::array<PoleInnovation, kPoleModeCount> inn;
  std::array<std::optional<double>, kPoleModeCount> ll;
  std::array<bool, kPoleModeCount> favoured{};
  for (PoleMode mode : kPoleModes) {
    const int k = mode_index(mode);
    if (!evaluated[k]) continue;
    const int v = slot_of_mode(mode);
    inn[k] = v < 0 ? free_.innovation(m) : on_[v].innovation(m, plates[v]);
    if (inn[k].valid) ll[k] = inn[k].log_likelihood;
    if (v >= 0) favoured[k] = impact_report_pending(v);
  }
  // A pole pressed firmly onto its plate is not free (StateEstimatorConfig::pressed_min_mps2).
  if (const int j = slot_of_mode(active); j >= 0 && vehicles_[j].initialised()) {
    const NormalForceEstimate f = on_[j].normal_force(plates[j]);
    if (throwing_[j] ||
        f.value_mps2 > std::max(config_.pressed_min_mps2, config_.pressed_sigmas * f.sigma_mps2))
      ll[mode_index(PoleMode::free)].reset();
  }
  if (active == PoleMode::free && launched_from_ >= 0 && t_s_ - launch_t_s_ < config_.launch_hold_off_s) {
    ll[mode_index(on_vehicle_mode(pa::kActVehicles[launched_from_]))].reset();
  }
  // A pose that no filter explains: a glitch, or (if it persists) a pole that is elsewhere.
  bool explained = false;
  for (PoleMode mode : kPoleModes) {
    const int k = mode_index(mode);
    explained |= evaluated[k] && inn[k].valid && inn[k].nis <= config_.pole_outlier_nis;
  }
  if (!explained) {
    pole_health_.rejected();
    if (++pole_rejections_ > config_.pole_max_rejections) {
      pole_seen_ = false;
      initialise_pole(m, SwitchReason::reinitialised);
    }
    return;
  }
  pole_rejections_ = 0;

  const bool holding_off = t_s_ - last_switch_detected_s_ < config_.switch_hold_off_s;
  if (holding_off) {
    selector_.reset(active);  // the candidates keep being re-seeded from the new estimate
  } else if (const std::optional<PoleMode> chosen = selector_.step(ll, favoured)) {
    // The selector has already made the switch; record it (at the reported impact if a report
    // favoured the mode).
    const PoleMode to = *chosen;
    const int v = slot_of_mode(to);
    const double event_t = v >= 0 && favoured[mode_index(to)] ? impact_report_t_s_[v] : t_s_;
    selector_.reset(active);
    switch_to(to, SwitchReason::innovation, event_t, t_s_);
  }
  pole_health_.innovation(inn[mode_index(selector_.active())].nis);

  // A free-flight candidate re-seeded below (reseed_candidates resets its state, covariance and
  // drag scale) is not corrected first.
  const bool free_reseeded = free_candidate_reseeded();
  for (PoleMode mode : kPoleModes) {
    const int k = mode_index(mode);
    if (!evaluated[k] || !inn[k].valid) continue;
    const int v = slot_of_mode(mode);
    if (v < 0) {
      if (!free_reseeded) free_.update(m, inn[k]);
    } else {
      on_[v].update(m, plates[v], inn[k]);
    }
  }
  reseed_candidates();
}

// ---------------------------------------------------------------------------------------------
// Outputs

PoleEstimate StateEstimator::pole() const {
  if (!pole_estimate_) pole_estimate_ = pole_now();
  return *pole_estimate_;
}

PoleEstimate StateEstimator::pole_now() const {
  PoleEstimate e;
  e.valid = pole_seen_;
  e.t_s = t_s_;
  e.mode = selector_.active();
  const int v = slot_of_mode(e.mode);
  if (v < 0 || !vehicles_[v].initialised()) {
    e.state = free_.state();
    e.covariance = free_.pole_covariance();
    e.drag_scale = free_.drag_scale();
  } else {
    const FreeFlightSeed s = free_flight_seed_from_on_vehicle(on_[v], vehicles_[v].plate());
    e.state = s.state;
    e.covariance = s.covariance;
    e.drag_scale = drag_scale_;
  }
  return e;
}

bool StateEstimator::vehicle_initialised(pa::VehicleId vehicle) const {
  return pa::is_act_vehicle(vehicle) && vehicles_[pa::act_slot(vehicle)].initialised();
}

VehicleEstimate StateEstimator::vehicle(pa::VehicleId vehicle) const {
  return vehicles_[pa::act_slot(vehicle)].estimate();
}

PlateKinematics StateEstimator::plate(pa::VehicleId vehicle) const {
  return vehicles_[pa::act_slot(vehicle)].plate();
}

std::optional<NormalForceEstimate> StateEstimator::normal_force() const {
  const int v = slot_of_mode(selector_.active());
  if (v < 0 || !vehicles_[v].initialised()) return std::nullopt;
  return on_[v].normal_force(vehicles_[v].plate());
}

StateEstimator StateEstimator::predicted(double t_s) const {
  StateEstimator ahead = *this;
  ahead.propagation_ = Propagation::mean_only;
  ahead.advance_to(t_s);
  return ahead;
}

PoleEstimate StateEstimator::predict_pole(double t_s) const { return predicted(t_s).pole(); }

VehicleEstimate StateEstimator::predict_vehicle(pa::VehicleId vehicle, double t_s) const {
  return predicted(t_s).vehicle(vehicle);
}

EstimatorHealth StateEstimator::health(double t_now_s) const {
  EstimatorHealth h;
  h.t_s = t_now_s;
  for (int i = 0; i < 2; ++i) h.vehicle[i] = snapshot(vehicle_health_[i], t_now_s);
  h.pole = snapshot(pole_health_, t_now_s);
  h.mode = selector_.active();
  h.time_in_mode_s = pole_seen_ ? t_now_s - mode_since_s_ : 0.0;
  h.mode_switches = switch_count_;
  h.frames = frames_;
  h.frames_out_of_order = frames_out_of_order_;
  if (pole_seen_) {
    const PoleEstimate e = pole();
    h.pole_position_sigma_m = std::sqrt(std::max(0.0, e.covariance.topLeftCorner<3, 3>().trace() / 3.0));
    h.drag_scale = e.drag_scale;
  }
  return h;
}

std::optional<ModeSwitch> StateEstimator::last_switch() const {
  if (switch_count_ == 0) return std::nullopt;
  return switch_log_[(switch_count_ - 1) % kSwitchLogCapacity];
}

std::vector<ModeSwitch> StateEstimator::recent_switches() const {
  std::vector<ModeSwitch> out;
  const std::uint64_t n = std::min<std::uint64_t>(switch_count_, kSwitchLogCapacity);
  out.reserve(n);
  for (std::uint64_t i = switch_count_ - n; i < switch_count_; ++i) {
    out.push_back(switch_log_[i % kSwitchLogCapacity]);
  }
  return out;
}

}  // namespace gs::estimation
