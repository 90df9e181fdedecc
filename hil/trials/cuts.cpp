#include "hil/trials/cuts.hpp"

#include <algorithm>
#include <cstdio>
#include <optional>
#include <random>
#include <stdexcept>

#include "fw/supervisor.hpp"
#include "hil/plant/randomisation.hpp"
#include "hil/trials/campaign.hpp"
#include "hil/trials/series.hpp"
#include "hil/trials/trial_config.hpp"
#include "hil/trials/worker_pool.hpp"

namespace hil::trials {
namespace {

using gs::mission::Task;
using pa::proto::Mode;

constexpr pa::VehicleId kThrower = pa::kVehicle1;
constexpr pa::VehicleId kCatcher = pa::kVehicle2;
// A pre-flight rest as long as the firmware's bias window (2000 IMU samples): the mission's
// ground station takes off at once otherwise, after 45 ms on the floor.
constexpr double kRestBeforeTakeOff_s = 2.0;
constexpr double kLostTilt_rad = 60.0 * M_PI / 180.0;

double tilt_of(const RigidBodyState& body) { return std::acos(std::clamp(body.rotation()(2, 2), -1.0, 1.0)); }

// The mission's phase from the ground station's tasks, in the order a mission flies them; a
// phase once left is not re-entered (the throw, then the catch manoeuvre, then after it).
class PhaseTracker {
 public:
  std::optional<CutPhase> update(Task thrower, Task catcher) {
    if (thrower == Task::throwing || thrower == Task::release) thrown_ = true;
    if (thrown_ && catcher == Task::catching) catching_ = true;
    if (catching_ && catcher != Task::catching) caught_ = true;
    if (caught_) return CutPhase::after_catch;
    if (catching_) return CutPhase::catching;
    if (thrown_) return CutPhase::throwing;
    const bool catcher_up = catcher == Task::hover || catcher == Task::wait;
    if (thrower == Task::balance && catcher_up) return CutPhase::balance;
    if (thrower == Task::hover && catcher_up) return CutPhase::hover;
    return std::nullopt;  // on the ground, arming, taking off
  }

 private:
  bool thrown_ = false, catching_ = false, caught_ = false;
};

long step_index(double t_s) { return std::lround(t_s * 1000.0); }

// Flies mission `mission` with `on_step(step, phase, arena)` after every step.
void fly_mission(const CutsConfig& config, const WarmUp& warm, std::uint64_t seed,
                 const std::function<void(long, std::optional<CutPhase>, const sil::Arena&)>& on_step) {
  SeriesConfig series = trial_config(config.plant, seed, PlantDraw::drawn);
  series.ground_station.learnt = warm.learnt;
  series.ground_station.fig5_throw = warm.fig5_throw;
  series.rest_before_take_off_s = kRestBeforeTakeOff_s;
  PhaseTracker phases;
  series.on_step = [&](const sil::Arena& arena, const gs::runtime::GroundStation& gs) {
    on_step(step_index(arena.t_s()), phases.update(gs.task(kThrower), gs.task(kCatcher)), arena);
  };
  SeriesRunner runner(series);
  runner.run({AttemptPlan{}});
}

std::vector<CutResult> fly_group(const CutsConfig& config, const WarmUp& warm, int mission) {
  const std::uint64_t seed = attempt_seed(config.seed, mission);
  // Where each phase begins and ends (steps), from a first flight.
  // And when the mission itself lost each vehicle (tilted past kLostTilt_rad), if it did: a
  // vehicle tumbling before its cut is the mission's failure, not the failsafe's.
  std::array<long, kCutPhaseCount> first{}, last{};
  first.fill(-1);
  std::array<long, 2> lost{-1, -1};
  fly_mission(config, warm, seed, [&](long k, std::optional<CutPhase> phase, const sil::Arena& arena) {
    for (const pa::VehicleId v : pa::kActVehicles) {
      long& at = lost[pa::act_slot(v)];
      if (at < 0 && tilt_of(arena.plant().vehicle(v).body) > kLostTilt_rad) at = k;
    }
    if (!phase) return;
    const auto p = static_cast<std::size_t>(*phase);
    if (first[p] < 0) first[p] = k;
    last[p] = k;
  });

  const int begin = (mission - 1) * config.cuts_per_mission + 1;
  const int end = std::min(config.cuts, mission * config.cuts_per_mission);
  std::mt19937_64 rng(seed ^ 0xC0FFEE5EEDull);
  std::vector<std::pair<long, int>> plan;  // (step, cut)
  for (int c = begin; c <= end; ++c) {
    int p = (c - 1) % kCutPhaseCount;
    for (int i = 0; i < kCutPhaseCount && first[static_cast<std::size_t>(p)] < 0; ++i)
      p = (p + 1) % kCutPhaseCount;
    const auto sp = static_cast<std::size_t>(p);
    const double u = static_cast<double>(rng() >> 11) * 0x1.0p-53;  // [0, 1), the same everywhere
    const long span = first[sp] < 0 ? 1 : last[sp] - first[sp] + 1;
    plan.emplace_back(std::max(0L, first[sp]) + static_cast<long>(u * static_cast<double>(span)), c);
  }
  std::sort(plan.begin(), plan.end());

  std::vector<CutResult> results;
  std::size_t next = 0;
  fly_mission(config, warm, seed, [&](long k, std::optional<CutPhase> phase, const sil::Arena& arena) {
    for (; next < plan.size() && plan[next].first <= k; ++next) {
      CutResult r = fly_cut(arena, config.limits);
      r.cut = plan[next].second;
      r.mission = mission;
      r.mission_seed = seed;
      r.phase = phase.value_or(CutPhase::hover);
      for (std::size_t i = 0; i < r.vehicles.size(); ++i) {
        std::string& failure = r.vehicles[i].failure;
        if (!failure.empty() && lost[i] >= 0 && plan[next].first >= lost[i])
          failure = std::string(kLostBeforeCut) + "+" + failure;
      }
      results.push_back(r);
    }
  });
  // A mission that ended before a planned step (it should not: the same seed flies the same
  // mission) leaves those cuts to its last state.
  if (next < plan.size()) throw std::runtime_error("mission " + std::to_string(mission) + " ended early");
  std::sort(results.begin(), results.end(),
            [](const CutResult& a, const CutResult& b) { return a.cut < b.cut; });
  return results;
}

constexpr double kDeg = 180.0 / M_PI;

// Every field of one vehicle's cut; the CSV's angles in degrees.
const Schema<VehicleCut>& vehicle_cut_schema() {
  using V = VehicleCut;
  static const Schema<V> schema{
      field("mode_at_cut", &V::mode_at_cut),
      field("height_m", &V::height_m, "%.3f"),
      field("tilt_at_cut_deg", &V::tilt_at_cut_rad, "%.2f", kDeg),
      field("failsafe_after_s", &V::failsafe_after_s, "%.3f"),
      field("levelled_after_s", &V::levelled_after_s, "%.3f"),
      field("max_tilt_deg", &V::max_tilt_rad, "%.2f", kDeg),
      field("touchdown_after_s", &V::touchdown_after_s, "%.3f"),
      field("touchdown_speed_mps", &V::touchdown_speed_mps, "%.4f"),
      field("touchdown_tilt_deg", &V::touchdown_tilt_rad, "%.2f", kDeg),
      field("drift_m", &V::drift_m, "%.3f"),
      field("final_mode", &V::final_mode),
      field("landed", &V::landed),
      field("motors_off", &V::motors_off),
      field("crashed", &V::crashed),
      field("failure", &V::failure),
  };
  return schema;
}

}  // namespace

std::string_view cut_phase_name(CutPhase phase) {
  switch (phase) {
    case CutPhase::hover: return "hover";
    case CutPhase::balance: return "balance";
    case CutPhase::throwing: return "throw";
    case CutPhase::catching: return "catch";
    case CutPhase::after_catch: return "after_catch";
  }
  return "unknown";
}

CutResult fly_cut(const sil::Arena& at_cut, const CutLimits& limits) {
  // A cut forks the mission: the arena is copied, which the images in QEMU cannot be.
  if (at_cut.emulated_firmware())
    throw std::invalid_argument(
        "cuts fork the mission's arena, which needs the firmware in process, not emulated");
  sil::Arena arena(at_cut);
  arena.silence_uplink();
  arena.take_ground_frames();
  arena.take_mocap();
  const double t_cut = arena.t_s();
  CutResult r;
  r.t_cut_s = t_cut;

  struct Watch {
    double last_setpoint_s = 0.0;
    Vec3 at_cut_m;
    bool levelled = false;
    bool done = false;
  };
  std::array<Watch, 2> watch;
  const Plant& plant = arena.plant();
  for (const pa::VehicleId v : pa::kActVehicles) {
    const std::size_t i = pa::act_slot(v);
    const sil::FirmwareVehicle& fw = arena.vehicle(v);
    const RigidBodyState& body = plant.vehicle(v).body;
    // The firmware's clock is its last IMU sample's, the arena's time (firmware_vehicle.hpp).
    const auto now_us = static_cast<std::uint32_t>(std::llround(t_cut * 1e6));
    const std::uint32_t age_us = fw.setpoint_age_us(now_us);
    watch[i].last_setpoint_s = age_us == sil::kNoSetpoint ? t_cut : t_cut - 1e-6 * age_us;
    watch[i].at_cut_m = body.position_m;
    VehicleCut& c = r.vehicles[i];
    c.mode_at_cut = pa::proto::mode_name(fw.observe().mode);
    c.height_m = body.position_m.z();
    c.tilt_at_cut_rad = c.max_tilt_rad = tilt_of(body);
  }
  r.min_separation_m =
      (plant.vehicle(pa::kVehicle1).body.position_m - plant.vehicle(pa::kVehicle2).body.position_m).norm();

  const double deadline = t_cut + limits.land_within_s;
  while (arena.t_s() < deadline && !(watch[0].done && watch[1].done)) {
    std::array<double, 2> vz_before{};
    std::array<bool, 2> floor_before{};
    for (const pa::VehicleId v : pa::kActVehicles) {
      vz_before[pa::act_slot(v)] = plant.vehicle(v).body.velocity_mps.z();
      floor_before[pa::act_slot(v)] = plant.vehicle_on_floor(v);
    }
    arena.step();
    arena.take_ground_frames();  // nobody listens
    arena.take_mocap();
    const double t = arena.t_s();
    r.min_separation_m = std::min(
        r.min_separation_m,
        (plant.vehicle(pa::kVehicle1).body.position_m - plant.vehicle(pa::kVehicle2).body.position_m).norm());
    for (const pa::VehicleId v : pa::kActVehicles) {
      const std::size_t i = pa::act_slot(v);
      Watch& w = watch[i];
      if (w.done) continue;
      VehicleCut& c = r.vehicles[i];
      const sil::FirmwareVehicle& fw = arena.vehicle(v);
      const pa::proto::Mode mode = fw.observe().mode;
      const RigidBodyState& body = plant.vehicle(v).body;
      const double tilt = tilt_of(body);
      // A setpoint that reached the vehicle before the cut may still be under its link guard's
      // check (docs/security.md) and be acted on just after: the last setpoint is the last one
      // received, as the firmware stamps it.
      if (c.failsafe_after_s < 0.0) {
        const auto now_us = static_cast<std::uint32_t>(std::llround(t * 1e6));
        const std::uint32_t age_us = fw.setpoint_age_us(now_us);
        if (age_us != sil::kNoSetpoint) w.last_setpoint_s = std::max(w.last_setpoint_s, t - 1e-6 * age_us);
      }
      const double since = t - w.last_setpoint_s;
      if (c.failsafe_after_s < 0.0 && fw::on_board_flight(mode)) c.failsafe_after_s = since;  // a hold first
      if (!w.levelled) c.max_tilt_rad = std::max(c.max_tilt_rad, tilt);
      if (!w.levelled && c.failsafe_after_s >= 0.0 && tilt < limits.level_tilt_rad &&
          body.rate_body_radps.cwiseAbs().maxCoeff() < limits.level_rate_radps) {
        w.levelled = true;
        c.levelled_after_s = since;
      }
      const bool on_floor = plant.vehicle_on_floor(v);
      if (c.touchdown_after_s < 0.0 && on_floor && !floor_before[i]) {
        c.touchdown_after_s = since;
        c.touchdown_speed_mps = -vz_before[i];
        c.touchdown_tilt_rad = tilt;
        c.drift_m = (body.position_m - w.at_cut_m).head<2>().norm();
      }
      const MotorCommands& motors = arena.exchange().motor_commands(v);
      c.motors_off =
          std::all_of(motors.command.begin(), motors.command.end(), [](double m) { return m == 0.0; });
      c.final_mode = pa::proto::mode_name(mode);
      c.landed = c.motors_off && on_floor;  // the firmware may say landed or killed
      // Over once the motors are off on the floor (landed, or killed and fallen).
      if (c.motors_off && on_floor && c.touchdown_after_s >= 0.0) {
        w.done = true;
        c.crashed = c.touchdown_speed_mps > limits.crash_speed_mps ||
                    c.touchdown_tilt_rad > limits.crash_tilt_rad || tilt > limits.crash_tilt_rad;
      }
    }
  }
  r.run_s = arena.t_s() - t_cut;

  for (VehicleCut& c : r.vehicles) {
    std::vector<std::string> causes;
    if (c.failsafe_after_s < 0.0) causes.emplace_back("no_hold");
    else if (c.failsafe_after_s > limits.failsafe_within_s + 1e-9) causes.emplace_back("failsafe_late");
    if (c.levelled_after_s < 0.0) causes.emplace_back("never_levelled");
    if (c.crashed) causes.emplace_back("crashed");
    if (!c.landed) causes.emplace_back("not_landed");
    if (!c.motors_off) causes.emplace_back("motors_on");
    for (const std::string& cause : causes) c.failure += (c.failure.empty() ? "" : "+") + cause;
  }
  return r;
}

const Schema<CutResult>& cut_schema() {
  static const Schema<CutResult> schema = [] {
    using R = CutResult;
    Field<R> phase = field("phase", &R::phase);
    phase.read = [](R& r, const std::string& text) {
      const int p = std::stoi(text);
      if (p < 0 || p >= kCutPhaseCount) throw std::out_of_range("no phase " + text);
      r.phase = static_cast<CutPhase>(p);
    };
    phase.cell = [](const R& r) { return std::string(cut_phase_name(r.phase)); };
    Schema<R> s{
        field("cut", &R::cut),
        field("mission", &R::mission),
        field("mission_seed", &R::mission_seed),
        phase,
        field("t_cut_s", &R::t_cut_s, "%.3f"),
        field("min_separation_m", &R::min_separation_m, "%.3f"),
        field("run_s", &R::run_s, "%.3f"),
    };
    for (std::size_t i = 0; i < 2; ++i) {
      for (const Field<VehicleCut>& f : vehicle_cut_schema())
        s.push_back(lift<R>(
            f, [i](auto& r) -> auto& { return r.vehicles[i]; }));
    }
    return s;
  }();
  return schema;
}

std::string encode_cuts(const std::vector<CutResult>& cuts) {
  std::string out;
  for (const CutResult& r : cuts) {
    if (!out.empty()) out += '|';
    out += encode(cut_schema(), r);
  }
  return out;
}

bool decode_cuts(const std::string& line, std::vector<CutResult>& cuts) {
  cuts.clear();
  if (line.empty()) return true;
  for (const std::string& record : split(line, '|')) {
    CutResult r;
    if (!decode(cut_schema(), record, r)) return false;
    cuts.push_back(r);
  }
  return true;
}

Schema<CutRow> cuts_csv_columns() {
  const auto cut = [](const CutRow& row) -> const CutResult& { return *row.cut; };
  const auto vehicle = [](const CutRow& row) -> const VehicleCut& {
    return row.cut->vehicles[pa::act_slot(row.vehicle)];
  };
  Schema<CutRow> out;
  for (const auto& f : columns(cut_schema(), {"cut", "mission", "mission_seed", "phase", "t_cut_s"}))
    out.push_back(column_of<CutRow>(f, cut));
  out.push_back(
      column<CutRow>("vehicle", [](const CutRow& row) { return std::to_string(int(row.vehicle.node())); }));
  for (const auto& f :
       columns(vehicle_cut_schema(),
               {"mode_at_cut", "height_m", "tilt_at_cut_deg", "failsafe_after_s", "levelled_after_s",
                "max_tilt_deg", "touchdown_after_s", "touchdown_speed_mps", "touchdown_tilt_deg", "drift_m"}))
    out.push_back(column_of<CutRow>(f, vehicle));
  out.push_back(column_of<CutRow>(columns(cut_schema(), {"min_separation_m"}).front(), cut));
  for (const auto& f :
       columns(vehicle_cut_schema(), {"final_mode", "landed", "motors_off", "crashed", "failure"}))
    out.push_back(column_of<CutRow>(f, vehicle));
  return out;
}

std::vector<CutResult> run_cuts(const CutsConfig& config, const std::function<void(int)>& progress) {
  if (config.cuts < 1 || config.jobs < 1 || config.cuts_per_mission < 1)
    throw std::runtime_error("cuts need cuts, jobs and cuts per mission >= 1");
  const WarmUp warm = warm_up(config.plant, config.seed);
  const int missions = (config.cuts + config.cuts_per_mission - 1) / config.cuts_per_mission;
  std::vector<CutResult> all(static_cast<std::size_t>(config.cuts));
  int done = 0;
  run_on_workers(
      missions, config.jobs, [&](int m) { return encode_cuts(fly_group(config, warm, m)); },
      [&](int m, const std::string& report) {
        std::vector<CutResult> cuts;
        if (!decode_cuts(report, cuts))
          throw std::runtime_error("mission " + std::to_string(m) + " reported unreadable cuts");
        for (const CutResult& r : cuts) {
          if (r.cut < 1 || r.cut > config.cuts) throw std::runtime_error("a cut out of range");
          all[static_cast<std::size_t>(r.cut - 1)] = r;
        }
        done += static_cast<int>(cuts.size());
        if (progress) progress(done);
      },
      "mission");
  return all;
}

}  // namespace hil::trials
