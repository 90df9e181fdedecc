#include "hil/trials/series.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

namespace hil::trials {
namespace {

using gs::adaptation::ThrowOutcome;
using gs::mission::Task;

constexpr double kUpright_rad = 5.0 * M_PI / 180.0;  // the acceptance's "within 5 degrees"
constexpr double kBalancedFor_s = 3.0;

double tilt_of(const PoleState& pole) { return std::acos(std::min(1.0, std::abs(pole.axis().z()))); }

Surface plate_of(pa::VehicleId vehicle) {
  return vehicle == pa::kVehicle1 ? Surface::plate1 : Surface::plate2;
}

}  // namespace

std::vector<AttemptPlan> paper_series() {
  std::vector<AttemptPlan> plans;
  plans.push_back(AttemptPlan{false, Eigen::Vector2d::Zero(), 0.0});
  for (int i = 0; i < 6; ++i) plans.push_back(AttemptPlan{true, Eigen::Vector2d(1.0, 0.0), 0.0});
  plans.push_back(AttemptPlan{});
  plans.push_back(AttemptPlan{});
  return plans;
}

std::vector<AttemptPlan> pass_series(int n) {
  std::vector<AttemptPlan> plans;
  if (n <= 0) return plans;
  plans.push_back(AttemptPlan{false, Eigen::Vector2d::Zero(), 0.0});  // adapts only
  for (int i = 0; i < n; ++i) {
    AttemptPlan p;
    p.thrower = i % 2 == 0 ? pa::kVehicle1 : pa::kVehicle2;
    p.place_pole = i == 0;
    p.thrower_catches_next = true;
    plans.push_back(p);
  }
  return plans;
}

std::vector<AttemptPlan> target_series(int n, const Eigen::Vector2d& origin_xy_m) {
  std::vector<AttemptPlan> plans;
  for (int i = 0; i < n; ++i) {
    // Directions 360/n degrees apart, in order, so that the catcher's move from one target to
    // the next is a chord of the circle and never crosses the thrower; distances 2.5, 3.0, ...
    // 4.5 m in turn.
    const double direction = 2.0 * M_PI * i / n;
    const double distance_m = 2.5 + 0.5 * (i % 5);
    AttemptPlan p;
    p.target_xy_m = origin_xy_m + distance_m * Eigen::Vector2d(std::cos(direction), std::sin(direction));
    plans.push_back(p);
  }
  return plans;
}

std::vector<AttemptPlan> catch_series(int n, bool trial_first) {
  std::vector<AttemptPlan> plans;
  if (n <= 0) return plans;
  if (trial_first) plans.push_back(AttemptPlan{false, Eigen::Vector2d::Zero(), 0.0});
  for (int i = trial_first ? 1 : 0; i < n; ++i) plans.push_back(AttemptPlan{});
  return plans;
}

namespace {
// The ground station holds the keys the arena's firmware was built with.
gs::runtime::GroundStationConfig with_simulation_keys(gs::runtime::GroundStationConfig c) {
  c.link.keys.clear();
  for (const pa::VehicleId v : pa::kActVehicles) c.link.keys.push_back({v, sil::simulation_key(v)});
  return c;
}
}  // namespace

SeriesRunner::SeriesRunner(const SeriesConfig& config)
    : config_(config),
      arena_(config.plant, config.arena, config.seed),
      gs_(bus_, with_simulation_keys(config.ground_station)) {}

void SeriesRunner::step() {
  if (config_.time_arena) {
    const auto start = std::chrono::steady_clock::now();
    arena_.step();
    arena_time_s_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  } else {
    arena_.step();
  }
  const double now = arena_.t_s();
  for (const pa::proto::Frame& f : arena_.take_ground_frames()) gs_.on_frame(f, now);
  for (const CapturedFrame& m : arena_.take_mocap()) {
    const gs::estimation::MocapFrame frame = sil::to_ground_station_frame(m);
    if (!config_.time_ground_station) {
      gs_.on_mocap(frame, now);
      continue;
    }
    const auto start = std::chrono::steady_clock::now();
    gs_.on_mocap(frame, now);
    frame_times_s_.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  gs_.tick(now);
  // What the person standing by with the pole sees of each vehicle on the ground station.
  for (const pa::VehicleId v : pa::kActVehicles) arena_.show_waiting_for_pole(v, gs_.waiting_for_pole(v));
  for (const pa::proto::Frame& f : bus_.take()) arena_.send_from_ground(f);
  if (config_.log) {
    for (const gs::runtime::MissionEvent& e : gs_.take_events()) {
      char line[200];
      std::snprintf(line, sizeof line, "%9.3f  vehicle %d: %s -> %s (%s)", e.t_s, int(e.vehicle.node()),
                    std::string(gs::mission::task_name(e.from)).c_str(),
                    std::string(gs::mission::task_name(e.to)).c_str(),
                    std::string(gs::mission::reason_name(e.reason)).c_str());
      config_.log(line);
    }
    for (const gs::link::ImpactReport& i : gs_.take_impacts()) {
      char line[200];
      std::snprintf(line, sizeof line, "%9.3f  IMPACT from vehicle %d at %.3f: class %d, peak %.1f m/s^2, %s",
                    now, int(i.vehicle.node()), i.t_s, int(i.classification), double(i.peak_mps2),
                    i.final ? "final" : "provisional");
      config_.log(line);
    }
    if (gs_.estimator().switch_count() != switches_logged_) {
      switches_logged_ = gs_.estimator().switch_count();
      if (const auto s = gs_.estimator().last_switch()) {
        char line[200];
        std::snprintf(line, sizeof line, "%9.3f  pole: %s -> %s (%s, event at %.3f)", now,
                      std::string(gs::estimation::pole_mode_name(s->from)).c_str(),
                      std::string(gs::estimation::pole_mode_name(s->to)).c_str(),
                      std::string(gs::estimation::switch_reason_name(s->reason)).c_str(), s->event_t_s);
        config_.log(line);
      }
    }
  } else {
    gs_.take_events();
    gs_.take_impacts();
  }
  for (const pa::VehicleId vehicle : pa::kActVehicles) {
    const sil::FirmwareObservation fw = arena_.vehicle(vehicle).observe();
    if (fw.mode == pa::proto::Mode::killed) crashed_ = true;
    const std::size_t i = pa::act_slot(vehicle);
    if (config_.log && fw.mode != firmware_modes_[i]) {
      char line[160];
      std::snprintf(line, sizeof line, "%9.3f  firmware %d: mode %d, failsafe reason %d, impacts %d", now,
                    int(vehicle.node()), int(fw.mode), int(fw.failsafe_reason), int(fw.impact_count));
      config_.log(line);
    }
    firmware_modes_[i] = fw.mode;
  }
  if (config_.on_step) config_.on_step(arena_, gs_);
  if (recording_ != nullptr && std::lround(now * 1000.0) % 10 == 0) recording_->push_back(time_sample(now));
}

TimeSample SeriesRunner::time_sample(double now) const {
  const Plant& p = arena_.plant();
  TimeSample s{now,
               p.vehicle(pa::kVehicle1).body.position_m,
               p.vehicle(pa::kVehicle2).body.position_m,
               p.pole().body.position_m,
               p.pole().axis(),
               std::string(gs::mission::task_name(gs_.task(pa::kVehicle1))),
               std::string(gs::mission::task_name(gs_.task(pa::kVehicle2))),
               {},
               {},
               {},
               {},
               {}};
  for (const pa::VehicleId vehicle : pa::kActVehicles) {
    const std::size_t i = pa::act_slot(vehicle);
    s.plate_m[i] = p.plate_centre_m(vehicle);
    s.plate_normal[i] = p.plate_normal(vehicle);
    s.pole_end_m[i] = pole_end_m(p.pole(), p.config().pole, static_cast<int>(i));
    const pa::proto::RateThrust cmd = arena_.vehicle(vehicle).observe().setpoint;
    s.thrust_cmd_mps2[i] = cmd.thrust_mps2;
    s.rate_cmd_radps[i] = Vec3(cmd.rate_radps[0], cmd.rate_radps[1], cmd.rate_radps[2]);
  }
  return s;
}

bool SeriesRunner::run_until(const std::function<bool()>& done, double timeout_s) {
  const double until = arena_.t_s() + timeout_s;
  while (arena_.t_s() < until) {
    step();
    if (done()) return true;
  }
  return false;
}

std::vector<AttemptResult> SeriesRunner::run(const std::vector<AttemptPlan>& plans,
                                             const std::function<void(const AttemptResult&)>& on_result) {
  std::vector<AttemptResult> results;
  run_until([] { return false; }, config_.rest_before_take_off_s);
  gs_.request_take_off();
  const bool airborne = run_until(
      [&] { return gs_.task(pa::kVehicle1) == Task::hover && gs_.task(pa::kVehicle2) == Task::hover; }, 10.0);
  for (std::size_t i = 0; i < plans.size(); ++i) {
    AttemptResult r;
    if (airborne) {
      r = fly(plans[i], static_cast<int>(i) + 1);
    } else {
      r.throw_number = static_cast<int>(i) + 1;
      r.outcome = ThrowOutcome::aborted;
      r.abort_reason = "take_off_failed";
      r.vehicle_crashed = crashed_;  // a take-off can end so too
    }
    results.push_back(r);
    if (on_result) on_result(r);
  }
  if (config_.land_after && airborne) land();
  return results;
}

void SeriesRunner::land() {
  // The person takes the pole down from whichever plate holds it, 2 m aside of the act's line
  // (as for a pack swap), then both vehicles land.
  Plant& plant = arena_.plant();
  for (const pa::VehicleId v : pa::kActVehicles)
    if (plant.pole_contact() == contact_of(plate_of(v))) plant.lay_pole_on_floor(Vec3(0.0, -2.0, 0.0));
  gs_.request_land();
  landed_ = run_until(
      [&] { return gs_.task(pa::kVehicle1) == Task::parked && gs_.task(pa::kVehicle2) == Task::parked; },
      20.0);
  if (config_.log) {
    char line[120];
    std::snprintf(line, sizeof line, "%9.3f  both vehicles %s", arena_.t_s(),
                  landed_ ? "landed and parked" : "NOT parked 20 s after the landing was requested");
    config_.log(line);
  }
}

namespace {

// The catcher's travel, as the paper's Fig. 10 counts it: the horizontal distance from the
// waiting point of the throw (the mission's, which the catcher holds to 5 cm before a throw
// starts) to where the pole came to it (the impact's point, or where the lower end came down
// through the catching height, on truth), with a practice throw's offset added, for every throw
// (a throw-only one too: how far the catcher would have had to go). The path a catcher flies
// also depends on aborts and on the manoeuvre's shape; this is what adapting the waiting point
// reduces. 0 when the pole never came down through that height.
double required_travel(const Eigen::Vector2d& waiting_xy_m, const std::vector<Vec3>& lower_end_m,
                       double catch_height_m, const Eigen::Vector2d& offset_m, const AttemptResult& r) {
  std::optional<Eigen::Vector2d> catch_xy;
  if (r.impact) catch_xy = Eigen::Vector2d(r.catch_x_m, r.catch_y_m);
  for (std::size_t i = 1; i < lower_end_m.size() && !catch_xy; ++i) {
    const Vec3& a = lower_end_m[i - 1];
    const Vec3& b = lower_end_m[i];
    if (a.z() > catch_height_m && b.z() <= catch_height_m) {
      const double f = (a.z() - catch_height_m) / (a.z() - b.z());
      catch_xy = (a + f * (b - a)).head<2>();
    }
  }
  if (!catch_xy) return 0.0;
  return (*catch_xy + offset_m - waiting_xy_m).norm();
}

}  // namespace

bool SeriesRunner::swap_pack(pa::VehicleId vehicle) {
  if (config_.log) {
    char line[160];
    std::snprintf(line, sizeof line, "%9.3f  vehicle %d: pack spent at %.2f V, landing to swap it",
                  arena_.t_s(), int(vehicle.node()), arena_.plant().battery(vehicle).voltage_V);
    config_.log(line);
  }
  // Taken down 2 m aside of the act's line, where neither vehicle lands or takes off.
  if (arena_.plant().pole_contact() == contact_of(plate_of(vehicle)))
    arena_.plant().lay_pole_on_floor(Vec3(0.0, -2.0, 0.0));
  gs_.request_land(vehicle);
  if (!run_until([&] { return gs_.task(vehicle) == Task::parked; }, 20.0)) return false;
  arena_.plant().swap_battery(vehicle);
  ++packs_swapped_;
  gs_.request_take_off(vehicle);
  return run_until([&] { return gs_.task(vehicle) == Task::hover; }, 15.0);
}

AttemptResult SeriesRunner::fly(const AttemptPlan& plan, int number) {
  AttemptResult r;
  r.throw_number = number;
  if (config_.record_time_series) {
    series_.emplace_back();
    recording_ = &series_.back();
  }
  Plant& plant = arena_.plant();
  const PlantConfig& pc = plant.config();
  const double m = pc.pole.mass_kg;
  const double theta_pole = plant.pole_transverse_inertia_kgm2();
  plant.take_contact_events();

  // A pass needs the pole balanced on the thrower, where the last attempt left it.
  if (!plan.place_pole && plant.pole_contact() != contact_of(plate_of(plan.thrower))) {
    r.outcome = ThrowOutcome::aborted;
    r.abort_reason = "pole_not_on_thrower";
    recording_ = nullptr;
    return r;
  }
  gs::runtime::AttemptRequest request;
  request.thrower =
      plan.stronger_throws && plan.place_pole ? gs_.stronger_thrower(plan.thrower) : plan.thrower;
  // A spent pack is swapped before the throw: the person takes the pole down if the thrower holds
  // it, the thrower lands for a fresh pack, and the pole goes up again as for a first throw.
  bool place_pole = plan.place_pole;
  if (config_.swap_spent_packs && gs_.pack_spent(request.thrower)) {
    if (!swap_pack(request.thrower)) {
      r.outcome = ThrowOutcome::aborted;
      r.abort_reason = "take_off_failed";
      return r;
    }
    place_pole = true;
  }
  request.catch_it = plan.catch_it;
  request.catch_offset_m = plan.catch_offset_m;
  request.target_xy_m = plan.target_xy_m;
  request.thrower_catches_next = plan.thrower_catches_next;
  const std::size_t reports_before = gs_.attempts().size();
  const std::uint64_t innovation_switches_before =
      gs_.estimator().switch_count(gs::estimation::SwitchReason::innovation);
  const pa::VehicleId thrower = request.thrower;
  const pa::VehicleId catcher = pa::other_vehicle(thrower);
  r.thrower = thrower.node();
  if (!gs_.request_attempt(request)) {
    r.outcome = ThrowOutcome::aborted;
    r.abort_reason = std::string(gs::runtime::GroundStation::refusal_name(gs_.refusal_kind()));
    return r;
  }

  // The person stands by to put the pole on the thrower hovering at the throw's origin.
  if (place_pole) arena_.hand_pole_to(thrower, gs_.throw_frame(thrower).origin_m);
  bool pushed = false;
  std::optional<double> throw_start_s, launch_s, impact_s, floor_s;
  double upright_since_s = -1.0;  // < 0: not upright on the catcher
  std::vector<Vec3> lower_end_m;  // the pole's lower end from the launch to where it stopped
  bool caught = false;
  const double deadline = arena_.t_s() + config_.attempt_timeout_s;
  bool gs_done = false;
  double gs_done_s = 0.0;
  crashed_ = false;

  while (arena_.t_s() < deadline) {
    step();
    const double t = arena_.t_s();
    if (!throw_start_s && gs_.task(thrower) == Task::throwing) throw_start_s = t;
    if (plan.push_sideways_m != 0.0 && !pushed && throw_start_s && t - *throw_start_s >= 2.2) {
      // The spoiled launch: thrower and pole moved sideways together, as by a gust.
      VehicleState v = plant.vehicle(thrower);
      PoleState pole = plant.pole();
      v.body.position_m.y() += plan.push_sideways_m;
      pole.body.position_m.y() += plan.push_sideways_m;
      plant.set_vehicle(thrower, v);
      plant.set_pole(pole);
      pushed = true;
    }
    for (const PoleContactEvent& e : plant.take_contact_events()) {
      if (!throw_start_s) continue;
      if (!launch_s && !e.begins && e.surface == plate_of(thrower) && e.t_s - *throw_start_s > 1.0)
        launch_s = e.t_s;
      if (launch_s && !impact_s && e.begins && e.surface == plate_of(catcher)) {
        impact_s = e.t_s;
        const Vec3 end = pole_end_m(plant.pole(), pc.pole, e.end);
        r.impact = true;
        r.catch_height_m = end.z();
        r.catch_x_m = end.x();
        r.catch_y_m = end.y();
        r.flight_s = e.t_s - *launch_s;
      }
      if (launch_s && !floor_s && e.begins && e.surface == Surface::floor) floor_s = e.t_s;
    }
    if (launch_s && !impact_s && !floor_s) {
      const PoleState& pole = plant.pole();
      const Vec3 a = pole_end_m(pole, pc.pole, 0), b = pole_end_m(pole, pc.pole, 1);
      lower_end_m.push_back(a.z() < b.z() ? a : b);
    }
    // The energy right after the impact (30 ms: the plate's shock absorber has taken the blow).
    if (impact_s && r.energy_error_J == 0.0 && t >= *impact_s + 0.03) {
      const PoleState& pole = plant.pole();
      const Vec3 n = pole.axis();
      const int low = pole_end_m(pole, pc.pole, 0).z() < pole_end_m(pole, pc.pole, 1).z() ? 0 : 1;
      const Vec3 end = pole_end_m(pole, pc.pole, low);
      // About the lower end, s from the centre of mass: E* = m g s, the pole at rest upright on it.
      const double s = std::abs(pc.pole.end_along_axis_m(low));
      const Vec3 w = pole.body.rate_inertial_radps();
      const Vec3 w_perp = w - w.dot(n) * n;
      const double e = m * pc.gravity_mps2 * (pole.body.position_m.z() - end.z()) +
                       0.5 * (m * s * s + theta_pole) * w_perp.squaredNorm();
      r.energy_error_J = e - m * pc.gravity_mps2 * s;
    }
    // Caught: on the catcher's plate within 5 degrees of upright for 3 s.
    if (impact_s && plant.pole_contact() == contact_of(plate_of(catcher)) &&
        tilt_of(plant.pole()) < kUpright_rad) {
      if (upright_since_s < 0.0) upright_since_s = t;
      if (t - upright_since_s >= kBalancedFor_s) caught = true;
    } else {
      upright_since_s = -1.0;
    }
    if (!gs_done && gs_.attempts().size() > reports_before) {
      gs_done = true;
      gs_done_s = t;
    }
    // The attempt is over when the ground station says so and the referee has seen enough.
    if (gs_done && (caught || floor_s || !impact_s || t - gs_done_s > 4.0)) break;
    if (caught && gs_done) break;
  }
  recording_ = nullptr;

  const gs::runtime::AttemptReport* report =
      gs_.attempts().size() > reports_before ? &gs_.attempts().back() : nullptr;
  r.vehicle_crashed = crashed_;
  if (!impact_s && launch_s && floor_s) r.flight_s = *floor_s - *launch_s;
  const gs::mission::Reason end = report ? report->catcher_end : gs::mission::Reason::none;
  if (report && config_.log) {
    const gs::runtime::VehicleThrust thrower_thrust = gs_.thrust_of(thrower);
    char line[640];
    std::snprintf(
        line, sizeof line,
        "  ground station: waiting (%.3f, %.3f), last target (%.3f, %.3f), predicted (%.3f, %.3f) "
        "at %.3f s after launch, catching height %.3f (this throw's (42) predicted at %.3f m, "
        "%.3f s), catcher at impact (%.3f, %.3f, %.3f); truth: lower end (%.3f, %.3f, %.3f) at %.3f s; "
        "thrower's thrust gain %.3f at %.2f V, ceiling %.1f m/s^2",
        report->waiting_xy_m.x(), report->waiting_xy_m.y(), report->last_target_xy_m.x(),
        report->last_target_xy_m.y(), report->predicted ? report->predicted->xy_m.x() : 0.0,
        report->predicted ? report->predicted->xy_m.y() : 0.0,
        report->predicted ? report->predicted->t_s : 0.0, report->catch_height_m,
        report->predicted_optimal ? report->predicted_optimal->height_m : 0.0,
        report->predicted_optimal ? report->predicted_optimal->t_s : 0.0,
        report->catcher_at_impact_m ? report->catcher_at_impact_m->x() : 0.0,
        report->catcher_at_impact_m ? report->catcher_at_impact_m->y() : 0.0,
        report->catcher_at_impact_m ? report->catcher_at_impact_m->z() : 0.0, r.catch_x_m, r.catch_y_m,
        r.catch_height_m, r.flight_s, thrower_thrust.gain, thrower_thrust.battery_V,
        gs_.thrust_ceiling_mps2(thrower));
    config_.log(line);
  }
  const gs::mission::Reason throw_end = report ? report->thrower_end : gs::mission::Reason::none;
  if (!plan.catch_it) {
    r.outcome = ThrowOutcome::throw_only;
  } else if (throw_end != gs::mission::Reason::throw_ended && !impact_s) {
    // The throw itself failed (the pole left the plate before T, or it was aborted): the
    // catcher had nothing to catch.
    r.outcome = ThrowOutcome::aborted;
    const gs::runtime::AttemptEnd ended = report ? report->end : gs::runtime::AttemptEnd::none;
    r.abort_reason = throw_end != gs::mission::Reason::none ? std::string(gs::mission::reason_name(throw_end))
                     : ended == gs::runtime::AttemptEnd::motors_unidentified
                         ? std::string(gs::runtime::attempt_end_name(ended))
                         : "no_throw";
  } else if (end == gs::mission::Reason::out_of_reach || end == gs::mission::Reason::infeasible ||
             end == gs::mission::Reason::abort_requested) {
    r.outcome = ThrowOutcome::aborted;
    r.abort_reason = std::string(gs::mission::reason_name(end));
  } else if (plan.catch_offset_m.norm() > 0.0) {
    r.outcome = ThrowOutcome::offset_practice;
  } else if (caught) {
    r.outcome = ThrowOutcome::caught;
  } else if (impact_s) {
    r.outcome = ThrowOutcome::dropped;
  } else if (!launch_s) {
    r.outcome = ThrowOutcome::aborted;
    r.abort_reason = report ? "no_launch" : "timeout";
  } else {
    r.outcome = ThrowOutcome::missed;
  }
  if (!r.impact) r.energy_error_J = 0.0;
  r.innovation_switches = static_cast<int>(
      gs_.estimator().switch_count(gs::estimation::SwitchReason::innovation) - innovation_switches_before);
  if (report) r.planned_height_m = report->catch_height_m;
  if (report && report->predicted_optimal) r.optimal_height_m = report->predicted_optimal->height_m;
  if (report)
    r.travel_m =
        required_travel(report->waiting_xy_m, lower_end_m, report->catch_height_m, plan.catch_offset_m, r);
  if (report && report->target_m) {
    const Eigen::Vector2d target = report->target_m->head<2>();
    if (report->converged_prediction)
      r.predicted_target_miss_m = (report->converged_prediction->xy_m - target).norm();
    if (r.impact) r.target_miss_m = (Eigen::Vector2d(r.catch_x_m, r.catch_y_m) - target).norm();
  }
  return r;
}

}  // namespace hil::trials
