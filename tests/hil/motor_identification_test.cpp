// Identification on vehicles drawn from the arena envelope (hil/config/envelope.yaml): each flies
// its take-off in the lockstep arena with the ground-station runtime, which identifies its motors'
// lag from the take-off's rate doublets and measures its thrust gain in hover, from frames and
// poses alone; the assertions read the drawn plant's truth. Prints both, vehicle by vehicle.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <string>

#include "hil/plant/plant_config.hpp"
#include "hil/trials/series.hpp"
#include "hil/trials/trial_config.hpp"

TEST_CASE("20 vehicles drawn from the envelope: motor lag within 10 %, thrust gain within 2 %") {
  hil::PlantConfig envelope;
  std::string error;
  REQUIRE(hil::load_plant_config(std::string(PA_SOURCE_DIR) + "/hil/config/envelope.yaml", envelope, error));
  int vehicles = 0;
  for (int draw = 1; draw <= 10; ++draw) {
    hil::trials::SeriesConfig config = hil::trials::trial_config(envelope, hil::trials::attempt_seed(1, draw),
                                                                 hil::trials::PlantDraw::drawn);
    hil::trials::SeriesRunner runner(config);
    runner.run({});  // the take-off, until both hover
    // The identification flight, then hover for the thrust gain.
    runner.hover_for(10.0);
    for (const pa::VehicleId v : pa::kActVehicles) {
      const std::size_t slot = pa::act_slot(v);
      const double lag_s =
          config.plant.vehicle.motor_time_constant_s * config.plant.vehicle.motor_time_constant_scale[slot];
      const double k_true = runner.arena().plant().true_thrust_gain(v);
      const auto& id = runner.ground_station().motor_identification(v);
      const double k = runner.ground_station().thrust_gain(v).gain();
      if (!id) {
        std::printf("draw %2d vehicle %u: not identified, task %s, thrust gain %.3f measured %.3f\n", draw,
                    static_cast<unsigned>(v.node()),
                    std::string(gs::mission::task_name(runner.ground_station().task(v))).c_str(), k_true, k);
      }
      REQUIRE(id);
      INFO("draw " << draw << " vehicle " << int(v.node()) << ": "
                   << gs::estimation::refusal_name(id->refusal));
      REQUIRE(id->identified);
      std::printf(
          "draw %2d vehicle %u: lag %.1f ms identified %.1f ms (%+.1f %%); thrust gain %.3f measured %.3f "
          "(%+.1f %%)\n",
          draw, static_cast<unsigned>(v.node()), 1e3 * lag_s, 1e3 * id->identified->time_constant_s,
          100.0 * (id->identified->time_constant_s / lag_s - 1.0), k_true, k, 100.0 * (k / k_true - 1.0));
      CHECK(id->identified->time_constant_s == Approx(lag_s).epsilon(0.1));
      CHECK(k == Approx(k_true).epsilon(0.02));
      ++vehicles;
    }
  }
  CHECK(vehicles == 20);
}
