// 100 passes back and forth on one battery each, starting full (`hil fly --passes 100` on the
// project's plant with battery_enabled): the packs sag from 12.6 V through the flight, the
// firmware compensates its motor commands for the voltage, and the ground station's thrust
// estimate follows each vehicle's gain. Every pass caught, and the estimate within 2 % of the
// plant's (its gain at the reference voltage, Plant::true_thrust_gain) once it has measured, at
// every second of the flight. Prints both, pass by pass.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "hil/plant/plant_config.hpp"
#include "hil/trials/series.hpp"
#include "hil/trials/trial_config.hpp"

TEST_CASE("100 passes on one full battery each: all caught, the thrust estimate within 2 % throughout") {
  hil::PlantConfig plant;
  std::string error;
  REQUIRE(hil::load_plant_config(std::string(PA_SOURCE_DIR) + "/hil/config/plant.yaml", plant, error));
  plant.battery.enabled = 1;
  hil::trials::SeriesConfig config = hil::trials::trial_config(plant, 1, hil::trials::PlantDraw::as_given);

  struct Worst {
    double error = 0.0;  // |estimate / plant - 1|
    double t_s = 0.0, estimate = 0.0, truth = 0.0;
  };
  std::array<Worst, 2> worst{};
  std::array<Worst, 2> last{};
  int samples = 0;
  double next_sample_s = 0.0;
  config.on_step = [&](const hil::sil::Arena& arena, const gs::runtime::GroundStation& station) {
    if (arena.t_s() < next_sample_s) return;
    next_sample_s = arena.t_s() + 1.0;
    for (const pa::VehicleId v : pa::kActVehicles) {
      const gs::estimation::ThrustGainEstimator& k = station.thrust_gain(v);
      if (k.sigma() > 0.01) continue;  // not yet measured: the airframe file's, then converging
      const double truth = arena.plant().true_thrust_gain(v);
      const Worst now{std::abs(k.gain() / truth - 1.0), arena.t_s(), k.gain(), truth};
      Worst& w = worst[pa::act_slot(v)];
      if (now.error > w.error) w = now;
      last[pa::act_slot(v)] = now;
      ++samples;
    }
  };
  hil::trials::SeriesRunner runner(config);
  const std::vector<hil::trials::AttemptResult> results =
      runner.run(hil::trials::pass_series(100), [&](const hil::trials::AttemptResult& r) {
        const hil::BatteryState& b1 = runner.arena().plant().battery(pa::kVehicle1);
        const hil::BatteryState& b2 = runner.arena().plant().battery(pa::kVehicle2);
        std::printf("pass %3d %-9s  vehicle 1: %.2f V, %3.0f %% charge, thrust gain %.4f estimated %.4f  "
                    "vehicle 2: %.2f V, %3.0f %% charge, thrust gain %.4f estimated %.4f\n",
                    r.throw_number - 1, std::string(gs::adaptation::to_string(r.outcome)).c_str(),
                    b1.voltage_V, 100.0 * b1.state_of_charge, last[0].truth, last[0].estimate, b2.voltage_V,
                    100.0 * b2.state_of_charge, last[1].truth, last[1].estimate);
      });
  for (const pa::VehicleId v : pa::kActVehicles) {
    const Worst& w = worst[pa::act_slot(v)];
    std::printf("vehicle %u: the thrust estimate's worst error %.2f %% at %.0f s (%.4f against %.4f)\n",
                static_cast<unsigned>(v.node()), 100.0 * w.error, w.t_s, w.estimate, w.truth);
    CHECK(w.error < 0.02);
  }
  CHECK(samples > 1000);
  REQUIRE(results.size() == 101);
  int caught = 0;
  for (std::size_t i = 1; i < results.size(); ++i) {
    INFO("pass " << i << ": " << gs::adaptation::to_string(results[i].outcome));
    CHECK(results[i].outcome == gs::adaptation::ThrowOutcome::caught);
    caught += results[i].outcome == gs::adaptation::ThrowOutcome::caught;
    CHECK_FALSE(results[i].vehicle_crashed);
  }
  std::printf("%d of 100 passes caught\n", caught);
  // The packs were drawn on: the voltage fell through the flight.
  CHECK(runner.arena().plant().battery(pa::kVehicle1).state_of_charge < 0.9);
}
