// The closed loop's cost: one whole ground-station frame (GroundStation::on_mocap: estimator
// update, latency compensation, mission, controllers and catch re-planning, link, both vehicles;
// the budget: a median of at most 50 us) and the whole arena (plant, two firmware cores, radios,
// motion capture and the ground station) as a multiple of real time on one core, both measured
// while flying a throw that adapts only and a catch (hil/trials/series.hpp). The Fig. 5 throw is
// planned once before, as a campaign plans it once for all its attempts (GroundStationConfig::
// fig5_throw): a flight does not plan it.
//
// Printed, per core (processor time, whatever else the machine runs): realtime_multiple, (b)
// the arena with the ground station; arena_realtime_multiple, (a) the arena alone (plant, both
// firmware cores, radios, motion capture: Arena::step) in the same flight, its calls timed by the
// wall clock (series.cpp); less_frames_realtime_multiple, the processor time less the
// ground-station frames (on_mocap), which also counts the ground station's construction,
// on_frame() and tick() and the runner's own work; plant_realtime_multiple, the truth plant
// alone (hil::Plant: the physics, the IMU and the motion capture's samples), replayed on the
// motor commands and the pole's handing that the flight gave it, and checked to end in the
// flight's state bit for bit. Wall-clock times overstate under load, so they are scaled by the
// run's processor over wall time; the replay is timed on the processor clock.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <ctime>
#include <optional>
#include <vector>

#include "hil/plant/plant.hpp"
#include "hil/trials/series.hpp"

namespace {

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(p * static_cast<double>(v.size() - 1))];
}

// What the plant was given in one 1 ms step of the flight.
struct PlantInput {
  std::array<hil::MotorCommands, 2> motors;
  std::optional<pa::VehicleId> pole_handed_to;  // a person put the pole on this vehicle first
};

// Steps `plant` through `inputs` and adds its processor time to `cpu_s`, taking its sensors'
// samples as the exchange does; false if it does not end in `end`'s state (then the replay was
// not the flight's physics).
bool replay_plant(hil::Plant plant, const std::vector<PlantInput>& inputs, const hil::Plant& end,
                  double& cpu_s) {
  const double period_s = 1.0 / static_cast<double>(plant.config().imu.rate_Hz);
  const std::clock_t start = std::clock();
  for (const PlantInput& in : inputs) {
    if (in.pole_handed_to) plant.place_pole_on(*in.pole_handed_to);
    plant.step(period_s, in.motors[0], in.motors[1]);
    hil::CapturedFrame frame;
    while (plant.pop_mocap(frame)) {
    }
    for (const pa::VehicleId v : pa::kActVehicles) {
      hil::ImuSample sample;
      while (plant.pop_imu(v, sample)) {
      }
    }
  }
  cpu_s += static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;
  const auto same = [](const hil::RigidBodyState& a, const hil::RigidBodyState& b) {
    return a.position_m == b.position_m && a.velocity_mps == b.velocity_mps;
  };
  return plant.t_s() == end.t_s() && same(plant.pole().body, end.pole().body) &&
         same(plant.vehicle(pa::kVehicle1).body, end.vehicle(pa::kVehicle1).body) &&
         same(plant.vehicle(pa::kVehicle2).body, end.vehicle(pa::kVehicle2).body);
}

void BM_ClosedLoopThrowAndCatch(benchmark::State& state) {
  std::vector<double> frames;
  double simulated_s = 0.0, cpu_s = 0.0, ground_station_s = 0.0, arena_s = 0.0, plant_s = 0.0;
  const hil::trials::SeriesConfig defaults;
  const auto fig5 =
      gs::planning::plan_fig5_throw(defaults.ground_station.limits, defaults.ground_station.throw_tracking);
  for (auto _ : state) {
    hil::trials::SeriesConfig config;
    config.seed = 1;
    config.ground_station.fig5_throw = fig5;
    config.time_ground_station = true;
    config.time_arena = true;
    // The plant's inputs, as the flight gave them: the motor commands a step ends with are held
    // over the next (run::PlantExchange), and the pole is handed up just before a step.
    std::vector<PlantInput> inputs;
    std::array<hil::MotorCommands, 2> held{};
    std::uint64_t handed = 0;
    config.on_step = [&](const hil::sil::Arena& arena, const gs::runtime::GroundStation&) {
      const std::uint64_t now_handed = arena.exchange().poles_handed();
      std::optional<pa::VehicleId> handed_to;
      if (now_handed != handed)
        handed_to = arena.plant().pole_contact() == hil::Contact::vehicle1 ? pa::kVehicle1 : pa::kVehicle2;
      inputs.push_back(PlantInput{held, handed_to});
      handed = now_handed;
      for (const pa::VehicleId v : pa::kActVehicles)
        held[pa::act_slot(v)] = arena.exchange().motor_commands(v);
    };
    const std::clock_t start = std::clock();
    const auto wall_start = std::chrono::steady_clock::now();
    hil::trials::SeriesRunner runner(config);
    const hil::Plant plant_at_start = runner.arena().plant();
    const auto results = runner.run(hil::trials::catch_series(2));
    // Processor time: the multiple per core, whatever else the machine runs.
    const double run_cpu_s = static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC;
    const double run_wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    cpu_s += run_cpu_s;
    simulated_s += runner.simulated_time_s();
    const auto& t = runner.ground_station_frame_times_s();
    frames.insert(frames.end(), t.begin(), t.end());
    double run_ground_station_s = 0.0;
    for (const double s : t) run_ground_station_s += s;
    ground_station_s += run_ground_station_s * std::min(1.0, run_cpu_s / run_wall_s);
    arena_s += runner.arena_time_s() * std::min(1.0, run_cpu_s / run_wall_s);
    benchmark::DoNotOptimize(results);
    if (!replay_plant(plant_at_start, inputs, runner.arena().plant(), plant_s)) {
      state.SkipWithError("the plant's replay did not end in the flight's state");
      return;
    }
  }
  state.counters["gs_frame_median_us"] = 1e6 * percentile(frames, 0.5);
  state.counters["gs_frame_p99_us"] = 1e6 * percentile(frames, 0.99);
  state.counters["gs_frames"] = static_cast<double>(frames.size());
  state.counters["realtime_multiple"] = simulated_s / cpu_s;
  state.counters["arena_realtime_multiple"] = simulated_s / arena_s;
  state.counters["less_frames_realtime_multiple"] = simulated_s / (cpu_s - ground_station_s);
  state.counters["plant_realtime_multiple"] = simulated_s / plant_s;
  state.counters["simulated_s"] = simulated_s;
}
BENCHMARK(BM_ClosedLoopThrowAndCatch)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace
