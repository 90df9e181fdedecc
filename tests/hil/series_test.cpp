// The closed loop in the lockstep arena (hil/trials/series.hpp): the ground-station runtime flies
// both vehicles through the real firmware and the radio, on its own estimate, from the floor.
// What it must do today: arm both vehicles over the protocol, take off, hold their points,
// take the pole a person puts on vehicle 1, balance it at the throw's origin and start the throw
// there. The ground station gets only frames and motion-capture poses; the assertions read the
// plant's truth.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "hil/plant/plant_config.hpp"
#include "hil/sil/firmware_vehicle.hpp"
#include "hil/trials/series.hpp"
#include "hil/trials/trial_config.hpp"

namespace {

using gs::adaptation::ThrowOutcome;
using gs::mission::Task;

struct Run {
  std::vector<hil::trials::AttemptResult> results;
  std::vector<std::string> log;
  std::vector<hil::trials::TimeSample> samples;
  int firmware_missed_ticks = 0;
  std::uint64_t link_undecodable = 0;
  bool throw_started = false;
};

const Run& throw_only() {
  static const Run run = [] {
    Run r;
    hil::trials::SeriesConfig config;
    config.seed = 3;
    config.record_time_series = true;
    config.attempt_timeout_s = 20.0;
    config.log = [&r](const std::string& line) { r.log.push_back(line); };
    hil::trials::SeriesRunner runner(config);
    r.results = runner.run({hil::trials::AttemptPlan{false, Eigen::Vector2d::Zero(), 0.0}});
    r.samples = runner.time_series().front();
    for (const pa::VehicleId vehicle : pa::kActVehicles)
      r.firmware_missed_ticks += static_cast<int>(runner.arena().exchange().counters(vehicle).missed);
    r.link_undecodable = runner.ground_station().link().counters().undecodable();
    for (const std::string& line : r.log)
      if (line.find("balance -> throwing") != std::string::npos) r.throw_started = true;
    return r;
  }();
  return run;
}

// The log for a failure message, without the estimator's restarts of the pole lying on the floor.
std::string joined(const std::vector<std::string>& log) {
  std::string out;
  for (const std::string& line : log)
    if (line.find("reinitialised") == std::string::npos) out += line + "\n";
  return out;
}

bool logged(const Run& r, const std::string& text) {
  for (const std::string& line : r.log)
    if (line.find(text) != std::string::npos) return true;
  return false;
}

}  // namespace

TEST_CASE("the ground station arms both vehicles over the radio and takes off on its estimate",
          "[hil][sil][runtime]") {
  const Run& r = throw_only();
  INFO(joined(r.log));
  // ARM through the link (heartbeat, zero-thrust setpoint, COMMAND, COMMAND_ACK) for both.
  CHECK(logged(r, "vehicle 1: parked -> arming (take_off_requested)"));
  CHECK(logged(r, "vehicle 2: parked -> arming (take_off_requested)"));
  CHECK(logged(r, "vehicle 1: arming -> take_off (armed)"));
  CHECK(logged(r, "vehicle 2: arming -> take_off (armed)"));
  CHECK(logged(r, "vehicle 1: take_off -> hover (airborne)"));
  CHECK(logged(r, "vehicle 2: take_off -> hover (airborne)"));
  CHECK(r.firmware_missed_ticks == 0);
  CHECK(r.link_undecodable == 0);
}

TEST_CASE("the pole put on vehicle 1 is balanced at the throw's origin, then the throw starts",
          "[hil][sil][runtime]") {
  const Run& r = throw_only();
  REQUIRE(logged(r, "vehicle 1: hover -> balance (pole_placed)"));
  REQUIRE(r.throw_started);
  // The last second before the throw: the truth pole within 3 degrees of upright and vehicle 1
  // within 10 cm of the throw's origin (plate at (0, 0, 2), the centre of gravity 3 cm below). The balancing LQR with the integral holds 0.5 degrees and a few centimetres
  // (measured with seed 3); a controller on a wrong state lets the pole fall within a second.
  double throw_t = 0.0;
  for (const hil::trials::TimeSample& s : r.samples)
    if (s.task1 == "throwing") {
      throw_t = s.t_s;
      break;
    }
  REQUIRE(throw_t > 0.0);
  int seen = 0;
  for (const hil::trials::TimeSample& s : r.samples) {
    if (s.t_s < throw_t - 1.0 || s.t_s >= throw_t) continue;
    ++seen;
    CHECK(std::acos(std::min(1.0, s.pole_axis.z())) < 3.0 * M_PI / 180.0);
    CHECK((s.vehicle1_m - Eigen::Vector3d(0.0, 0.0, 1.97)).norm() < 0.10);
  }
  CHECK(seen >= 90);
  // Vehicle 2 held its point meanwhile.
  for (const hil::trials::TimeSample& s : r.samples) {
    if (s.t_s < throw_t - 1.0 || s.t_s >= throw_t) continue;
    CHECK(std::abs(s.vehicle2_m.z() - 1.0) < 0.1);
  }
}

TEST_CASE("hil::trials::paper_series is the paper's nine throws", "[hil][sil][runtime]") {
  const std::vector<hil::trials::AttemptPlan> plans = hil::trials::paper_series();
  REQUIRE(plans.size() == 9);
  CHECK_FALSE(plans[0].catch_it);
  for (int i = 1; i < 7; ++i) CHECK(plans[i].catch_offset_m.norm() == Approx(1.0));
  CHECK(plans[7].catch_offset_m.norm() == 0.0);
  CHECK(plans[8].catch_it);
  const std::vector<hil::trials::AttemptPlan> catches = hil::trials::catch_series(3);
  REQUIRE(catches.size() == 3);
  CHECK_FALSE(catches[0].catch_it);
  CHECK(catches[2].catch_it);
}

namespace {

struct Series {
  std::vector<hil::trials::AttemptResult> results;
  std::vector<std::string> log;
  bool crashed = false;
  std::vector<double> throw_starts_s;  // the ground station's, attempt by attempt
};

Series fly(const std::vector<hil::trials::AttemptPlan>& plans, std::uint64_t seed) {
  Series s;
  hil::trials::SeriesConfig config;
  config.seed = seed;
  config.log = [&s](const std::string& line) { s.log.push_back(line); };
  hil::trials::SeriesRunner runner(config);
  s.results = runner.run(plans);
  for (const auto& r : s.results) s.crashed = s.crashed || r.vehicle_crashed;
  for (const auto& a : runner.ground_station().attempts()) s.throw_starts_s.push_back(a.throw_start_s);
  return s;
}

const Series& paper_series() {
  static const Series s = fly(hil::trials::paper_series(), 1);
  return s;
}

}  // namespace

TEST_CASE("the paper's series in the closed loop: throws 8 and 9 caught and balanced again",
          "[hil][sil][runtime][series]") {
  const Series& s = paper_series();
  REQUIRE(s.results.size() == 9);
  for (const auto& r : s.results) {
    INFO("throw " << r.throw_number << ": " << gs::adaptation::to_string(r.outcome) << " " << r.abort_reason);
    CHECK_FALSE(r.vehicle_crashed);
  }
  CHECK(s.results[0].outcome == ThrowOutcome::throw_only);
  for (int i = 1; i < 7; ++i) CHECK(s.results[i].outcome == ThrowOutcome::offset_practice);
  // Caught: the referee saw the pole on the catcher's plate within 5 degrees of upright for 3 s
  // after the impact (plant truth).
  CHECK(s.results[7].outcome == ThrowOutcome::caught);
  CHECK(s.results[8].outcome == ThrowOutcome::caught);
  // The pole's energy right after the impact, against E* = m_p g L (the paper: within 0.0102 J
  // on average). Measured with seed 1: -0.0030 and -0.0031 J.
  const double mean_error =
      0.5 * (std::abs(s.results[7].energy_error_J) + std::abs(s.results[8].energy_error_J));
  CHECK(s.results[7].impact);
  CHECK(s.results[8].impact);
  CHECK(mean_error <= 0.0102);
  // The catcher's travel falls over the series as in Fig. 10: throw 1 waits at the nominal
  // catch point, the later ones at the adapted one, and the travel comes down to the spread of
  // the catch point (measured with seed 1: 0.372 m, then 0.001-0.023 m).
  const auto travel = [&](int throw_number) { return s.results[throw_number - 1].travel_m; };
  CHECK(travel(1) > 0.1);
  for (int i = 2; i <= 9; ++i) {
    INFO("throw " << i);
    CHECK(travel(i) < travel(1) / 3.0);
  }
  CHECK((travel(6) + travel(7) + travel(8) + travel(9)) / 4.0 < (travel(1) + travel(2) + travel(3)) / 3.0);
}

TEST_CASE("a series is reproducible from its seed", "[hil][sil][runtime][series]") {
  const std::vector<hil::trials::AttemptPlan> plans = hil::trials::catch_series(2);
  const Series a = fly(plans, 5);
  const Series b = fly(plans, 5);
  REQUIRE(a.results.size() == b.results.size());
  for (std::size_t i = 0; i < a.results.size(); ++i) {
    CHECK(a.results[i].outcome == b.results[i].outcome);
    CHECK(a.results[i].flight_s == b.results[i].flight_s);
    CHECK(a.results[i].catch_x_m == b.results[i].catch_x_m);
    CHECK(a.results[i].energy_error_J == b.results[i].energy_error_J);
    CHECK(a.results[i].travel_m == b.results[i].travel_m);
  }
  CHECK(a.log == b.log);
}

TEST_CASE("a spoiled launch is aborted as out of reach and the mission goes on",
          "[hil][sil][runtime][series]") {
  // The thrower pushed 1.5 m sideways 0.3 s before the launch: the pole flies 1.5 m off the
  // waiting point, beyond the catch's reach (1 m).
  std::vector<hil::trials::AttemptPlan> plans = hil::trials::catch_series(3);
  plans[1].push_sideways_m = 1.5;
  const Series s = fly(plans, 1);
  INFO(joined(s.log));
  REQUIRE(s.results.size() == 3);
  CHECK(s.results[1].outcome == ThrowOutcome::aborted);
  CHECK(s.results[1].abort_reason == "out_of_reach");
  CHECK_FALSE(s.crashed);
  // The next attempt is flown (and caught).
  CHECK(s.results[2].outcome == ThrowOutcome::caught);
}

TEST_CASE("the adaptation store keeps what a series learnt for the next run", "[hil][sil][runtime][series]") {
  // In the temporary directory, so a run from the source tree leaves nothing behind.
  const std::string path =
      (std::filesystem::temp_directory_path() / "series_test_adaptation.sqlite").string();
  std::remove(path.c_str());
  std::remove((path + "-wal").c_str());
  std::remove((path + "-shm").c_str());
  gs::adaptation::Learnt learnt;
  {
    hil::trials::SeriesConfig config;
    config.seed = 2;
    config.ground_station.adaptation_store_path = path;
    hil::trials::SeriesRunner runner(config);
    const auto results = runner.run(hil::trials::catch_series(2));
    REQUIRE(results.size() == 2);
    learnt = runner.ground_station().learnt();
    CHECK(learnt.state.catch_point_samples == 2);
  }
  // A new ground station on the same store starts where the first stopped.
  gs::link::InMemoryFrameBus bus;
  gs::runtime::GroundStationConfig config;
  config.adaptation_store_path = path;
  for (const pa::VehicleId v : pa::kActVehicles) config.link.keys.push_back({v, hil::sil::simulation_key(v)});
  const gs::runtime::GroundStation restarted(bus, config);
  CHECK(restarted.adaptation() == learnt.state);
  CHECK(restarted.learnt().catch_instant_s == Approx(learnt.catch_instant_s));
  CHECK(restarted.throw_records().empty());
  // Each take-off's motor identification was recorded, and the restarted ground station flies
  // each vehicle with its last accepted one (adaptation/identification_memory.hpp).
  const gs::adaptation::AdaptationStore store = gs::adaptation::AdaptationStore::open_existing(path);
  CHECK(store.identification_count() >= 2);
  for (const pa::VehicleId v : pa::kActVehicles) {
    const std::optional<gs::adaptation::StoredIdentification> last = store.last_accepted_identification(v);
    const std::optional<gs::estimation::MotorIdentification>& kept = restarted.kept_motor_identification(v);
    INFO("vehicle " << int(v.node()));
    REQUIRE(kept.has_value() == last.has_value());
    if (kept) CHECK(kept->time_constant_s == last->record.result.identified->time_constant_s);
  }
}

TEST_CASE("passes back and forth: vehicle 2 catches, balances and throws back to vehicle 1",
          "[hil][sil][runtime][series]") {
  const std::vector<hil::trials::AttemptPlan> plans = hil::trials::pass_series(4);
  REQUIRE(plans.size() == 5);
  CHECK_FALSE(plans[0].catch_it);  // the throw that adapts
  CHECK(plans[1].place_pole);
  CHECK_FALSE(plans[2].place_pole);
  CHECK(plans[2].thrower == pa::kVehicle2);
  const Series s = fly(plans, 1);
  INFO(joined(s.log));
  REQUIRE(s.results.size() == 5);
  for (std::size_t i = 1; i < s.results.size(); ++i) CHECK(s.results[i].outcome == ThrowOutcome::caught);
  CHECK_FALSE(s.crashed);
  // Vehicle 1's throws come down on vehicle 2 some 3.6 m along +x; vehicle 2's come back to
  // where vehicle 1 throws from (x = 0), without a person putting the pole back.
  CHECK(s.results[1].catch_x_m > 3.0);
  CHECK(s.results[3].catch_x_m > 3.0);
  CHECK(std::abs(s.results[2].catch_x_m) < 0.3);
  CHECK(std::abs(s.results[4].catch_x_m) < 0.3);
  // The thrower retreats at the height it will wait at, and the catcher carries the pole down to
  // its own throw's origin while the catch is judged: from one pass's throw to the next in under
  // 11 s (15 s when the thrower retreated down to its origin and the catcher waited for the
  // judgement, then for 5 cm at its origin).
  REQUIRE(s.throw_starts_s.size() == 5);
  for (std::size_t i = 2; i < s.throw_starts_s.size(); ++i) {
    CAPTURE(i, s.throw_starts_s[i] - s.throw_starts_s[i - 1]);
    CHECK(s.throw_starts_s[i] - s.throw_starts_s[i - 1] < 11.0);
  }
}

TEST_CASE("a pass whose pole is not on its thrower is not flown", "[hil][sil][runtime][series]") {
  // The first pass does not place the pole: nobody put it back on vehicle 1 after the throw
  // that adapts.
  std::vector<hil::trials::AttemptPlan> plans = hil::trials::pass_series(2);
  plans[1].place_pole = false;
  const Series s = fly(plans, 1);
  REQUIRE(s.results.size() == 3);
  CHECK(s.results[1].outcome == ThrowOutcome::aborted);
  CHECK(s.results[1].abort_reason == "pole_not_on_thrower");
  CHECK(s.results[2].abort_reason == "pole_not_on_thrower");
}

TEST_CASE("throws to targets all round: vehicle 1 throws where vehicle 2 waits, and it catches",
          "[hil][sil][runtime][series][target_throw]") {
  const std::vector<hil::trials::AttemptPlan> plans = hil::trials::target_series(4, Eigen::Vector2d::Zero());
  REQUIRE(plans.size() == 4);
  // Directions 0, 90, 180 and 270 degrees (with the planar (42) the throws along y were dropped),
  // 2.5 to 4 m away.
  CHECK((*plans[1].target_xy_m - Eigen::Vector2d(0.0, 3.0)).norm() < 1e-12);
  CHECK((*plans[3].target_xy_m - Eigen::Vector2d(0.0, -4.0)).norm() < 1e-12);
  const Series s = fly(plans, 1);
  INFO(joined(s.log));
  REQUIRE(s.results.size() == 4);
  for (const hil::trials::AttemptResult& r : s.results) {
    CHECK(r.outcome == ThrowOutcome::caught);
    // The true impact near the target (the first throw, before any aim is learnt, within
    // 0.12 m; measured 0.09), the later ones closer (measured 0.003-0.03 m).
    CHECK(r.target_miss_m >= 0.0);
    CHECK(r.target_miss_m < 0.15);
    CHECK(r.predicted_target_miss_m >= 0.0);
    CHECK(r.predicted_target_miss_m < 0.15);
  }
  CHECK(s.results[3].target_miss_m < 0.06);
  CHECK_FALSE(s.crashed);
}

TEST_CASE("radio outages and motion-capture dropouts while the pole flies: holds, no failsafe, caught",
          "[hil][sil][runtime][series][outages]") {
  // The fault profile hil/config/radio_outages.yaml: both radios out 20 % of the time in 100 ms
  // outages, each body hidden from the motion capture 20 % of the time in 100 ms outages, only
  // between the throw and the catch.
  hil::PlantConfig plant;
  std::string error;
  const bool loaded = hil::load_plant_config(PA_SOURCE_DIR "/hil/config/radio_outages.yaml", plant, error);
  INFO(error);
  REQUIRE(loaded);
  hil::trials::SeriesConfig config = hil::trials::trial_config(plant, 6, hil::trials::PlantDraw::as_given);
  Series s;
  config.log = [&s](const std::string& line) { s.log.push_back(line); };
  int holds_in_flight = 0, firmware_failsafes = 0, mission_failsafes = 0;
  std::array<pa::proto::Mode, 2> last{pa::proto::Mode::disarmed, pa::proto::Mode::disarmed};
  std::array<bool, 2> in_failsafe_task{};
  config.on_step = [&](const hil::sil::Arena& arena, const gs::runtime::GroundStation& gs) {
    const bool pole_flies = arena.plant().pole_contact() == hil::Contact::none;
    for (const pa::VehicleId v : pa::kActVehicles) {
      const std::size_t i = pa::act_slot(v);
      const pa::proto::Mode mode = arena.vehicle(v).firmware().mode();
      if (mode != last[i] && mode == pa::proto::Mode::hold && pole_flies) ++holds_in_flight;
      if (mode != last[i] &&
          (mode == pa::proto::Mode::failsafe_hover || mode == pa::proto::Mode::failsafe_descent))
        ++firmware_failsafes;
      last[i] = mode;
      const bool failsafe_task = gs.task(v) == Task::failsafe;
      if (failsafe_task && !in_failsafe_task[i]) ++mission_failsafes;
      in_failsafe_task[i] = failsafe_task;
    }
  };
  hil::trials::SeriesRunner runner(config);
  // The paper's protocol: a throw that adapts only (the waiting point learnt), then the catches.
  s.results = runner.run(hil::trials::catch_series(4));
  INFO(joined(s.log));
  // The faults happened: frames lost both ways on both radios, and the firmware held.
  for (const pa::VehicleId v : pa::kActVehicles) {
    CHECK(runner.arena().exchange().counters(v).uplink_lost > 0);
    CHECK(runner.arena().exchange().counters(v).downlink_lost > 0);
  }
  CHECK(holds_in_flight >= 3);
  // ... and cost no failsafe, on board or in the mission, and no catch.
  CHECK(firmware_failsafes == 0);
  CHECK(mission_failsafes == 0);
  REQUIRE(s.results.size() == 4);
  CHECK(s.results[0].outcome == ThrowOutcome::throw_only);
  for (std::size_t i = 1; i < s.results.size(); ++i) CHECK(s.results[i].outcome == ThrowOutcome::caught);
}

TEST_CASE("a thrower whose pack is spent lands, gets a full one and throws", "[hil][sil][runtime]") {
  // Both packs at 30 %: about 11.2 V in hover, a ceiling of 0.79 a_full, below 1.15 times the
  // Fig. 5 throw's peak. Vehicle 1 throws: its pack is swapped first; vehicle 2 only catches.
  hil::trials::SeriesConfig config;
  config.plant.battery.enabled = 1;
  config.plant.battery.charge_start = {0.3, 0.3};
  config.swap_spent_packs = true;
  std::vector<std::string> log;
  config.log = [&log](const std::string& line) { log.push_back(line); };
  hil::trials::SeriesRunner runner(config);
  const std::vector<hil::trials::AttemptResult> results = runner.run(hil::trials::catch_series(2));
  INFO(joined(log));
  REQUIRE(results.size() == 2);
  CHECK(results[1].outcome == ThrowOutcome::caught);
  CHECK(runner.packs_swapped() == 1);
  CHECK(runner.arena().plant().battery(pa::kVehicle1).state_of_charge > 0.9);
  CHECK(runner.arena().plant().battery(pa::kVehicle2).state_of_charge < 0.3);
  bool landed = false;
  for (const std::string& line : log)
    landed |= line.find("vehicle 1: landing -> parked (landed)") != std::string::npos;
  CHECK(landed);
}

TEST_CASE("a vehicle that leaves the arena's volume lands where it is", "[hil][sil][runtime]") {
  // A ceiling at 0.8 m, below the take-off height (1.0 m): both vehicles cross it climbing and
  // are sent to land.
  Run r;
  hil::trials::SeriesConfig config;
  config.seed = 3;
  config.log = [&r](const std::string& line) { r.log.push_back(line); };
  gs::runtime::ArenaVolume volume;
  volume.min_m = Eigen::Vector3d(-4.0, -4.0, 0.0);
  volume.max_m = Eigen::Vector3d(8.0, 4.0, 0.8);
  config.ground_station.arena_volume = volume;
  hil::trials::SeriesRunner runner(config);
  runner.run({});
  runner.hover_for(8.0);
  INFO(joined(r.log));
  CHECK(runner.ground_station().volume_breaches() == 2);
  for (const pa::VehicleId v : pa::kActVehicles) {
    const std::string name = "vehicle " + std::to_string(v.node());
    CHECK(logged(r, name + ": take_off -> descend (land_requested)"));
    CHECK(logged(r, name + ": descend -> landing (near_floor)"));
    CHECK(logged(r, name + ": landing -> parked"));
    // The plant's truth: down on the floor.
    CHECK(runner.arena().plant().vehicle(v).body.position_m.z() < 0.2);
  }
}
