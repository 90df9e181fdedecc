// The launch seen by the ground station's estimator in the closed loop, on a plant drawn from
// the arena envelope whose throw turns the pole fast off a tilted plate: its end slides along
// the plate's plane for tens of milliseconds after the contact force vanished. The pole is
// launched once: the innovations do not put it back on the thrower's plate
// (StateEstimatorConfig::launch_hold_off_s), which would re-seed the free flight from the
// on-vehicle estimate at the second launch.
#include <catch2/catch.hpp>

#include <cstdio>
#include <string>

#include "hil/plant/plant_config.hpp"
#include "hil/trials/campaign.hpp"
#include "hil/trials/series.hpp"
#include "hil/trials/trial_config.hpp"

namespace {

using gs::estimation::PoleMode;
using gs::estimation::SwitchReason;

struct LaunchCount {
  int launches = 0;  // switches to free by the contact force
  int returned = 0;  // switches back to an on-vehicle mode by the innovations, before a catch
  bool caught = false;
};

// Attempt `attempt` of `hil campaign --seed 1 --plant hil/config/envelope.yaml`, without the
// campaign's warm-up. Attempt 29: without the hold-off the pole was launched 4 times.
LaunchCount fly_attempt(int attempt, double launch_hold_off_s) {
  hil::PlantConfig envelope;
  std::string error;
  REQUIRE(hil::load_plant_config(std::string(PA_SOURCE_DIR) + "/hil/config/envelope.yaml", envelope, error));
  hil::trials::SeriesConfig config = hil::trials::trial_config(
      envelope, hil::trials::attempt_seed(1, attempt), hil::trials::PlantDraw::drawn);
  config.ground_station.estimator.launch_hold_off_s = launch_hold_off_s;
  LaunchCount count;
  std::uint64_t seen = 0;
  bool in_flight = false;
  config.on_step = [&](const hil::sil::Arena&, const gs::runtime::GroundStation& gs) {
    const gs::estimation::StateEstimator& estimator = gs.estimator();
    if (estimator.switch_count() == seen) return;
    seen = estimator.switch_count();
    const gs::estimation::ModeSwitch s = *estimator.last_switch();
    if (s.to == PoleMode::free && s.reason == SwitchReason::contact_force) {
      ++count.launches;
      in_flight = true;
    } else if (in_flight && s.to != PoleMode::free) {
      if (s.reason == SwitchReason::innovation && !count.caught) ++count.returned;
      if (s.reason == SwitchReason::plate_contact || s.reason == SwitchReason::impact_report)
        count.caught = true;
    }
  };
  hil::trials::SeriesRunner runner(config);
  runner.run({hil::trials::campaign_attempt_plan()});
  return count;
}

}  // namespace

TEST_CASE("a pole launched off a turning plate is launched once") {
  const LaunchCount without = fly_attempt(29, 0.0);
  const LaunchCount with = fly_attempt(29, gs::estimation::StateEstimatorConfig{}.launch_hold_off_s);
  std::printf(
      "envelope attempt 29: without the hold-off %d launches, %d returns to a plate by the innovations; "
      "with it %d launches, %d returns\n",
      without.launches, without.returned, with.launches, with.returned);
  CHECK(without.returned > 0);  // the attempt shows what the hold-off is for
  CHECK(with.returned == 0);
  CHECK(with.launches == 1);
}
