// Identification on vehicles drawn from the arena envelope (hil/config/envelope.yaml): each flies
// its take-off in the lockstep arena with the ground-station runtime, which identifies its motors'
// lag from the take-off's rate doublets and measures its thrust gain in hover, from frames and
// poses alone; the assertions read the drawn plant's truth. Prints both, vehicle by vehicle. And a
// stored identification set on board at arming (adaptation/identification_memory.hpp).
#include <catch2/catch.hpp>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>

#include "groundstation/adaptation/adaptation_store.hpp"

#include "hil/plant/plant_config.hpp"
#include "hil/trials/campaign.hpp"
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

namespace {

// The campaign on the plant file `plant` (of the repository) with `seed` (hil campaign --plant).
hil::trials::CampaignConfig campaign_on(const std::string& plant, std::uint64_t seed) {
  hil::trials::CampaignConfig campaign;
  std::string error;
  REQUIRE(hil::load_plant_config(std::string(PA_SOURCE_DIR) + "/" + plant, campaign.plant, error));
  campaign.seed = seed;
  return campaign;
}

// The motor lag campaign attempt `attempt`'s plant gave `vehicle`, its `role` in the attempt
// flown as `r`: the ground station identified it, within 10 % (printed beside the truth).
void check_identified(const hil::trials::SeriesConfig& config, const hil::trials::SeriesRunner& runner,
                      int attempt, const char* role, pa::VehicleId vehicle,
                      const hil::trials::AttemptResult& r) {
  const double lag_s = config.plant.vehicle.motor_time_constant_s *
                       config.plant.vehicle.motor_time_constant_scale[pa::act_slot(vehicle)];
  const auto& id = runner.ground_station().motor_identification(vehicle);
  INFO("attempt " << attempt << ": " << role << " " << int(vehicle.node()) << ", lag " << lag_s << " s, "
                  << (id ? gs::estimation::refusal_name(id->refusal) : "no identification"));
  REQUIRE(id);
  REQUIRE(id->identified);
  std::printf("attempt %d %s %u: lag %.1f ms identified %.1f ms; %s\n", attempt, role,
              static_cast<unsigned>(vehicle.node()), 1e3 * lag_s, 1e3 * id->identified->time_constant_s,
              std::string(gs::adaptation::to_string(r.outcome)).c_str());
  CHECK(id->identified->time_constant_s == Approx(lag_s).epsilon(0.1));
}

// The arena envelope's campaign with `seed` (hil campaign --plant hil/config/envelope.yaml).
hil::trials::CampaignConfig envelope_campaign(std::uint64_t seed) {
  return campaign_on("hil/config/envelope.yaml", seed);
}

}  // namespace

// Two catchers of the envelope campaign (seed 1) that flew unequalised at 30 ms and dropped the
// pole, one crashing: attempt 287's (59.7 ms, weak) saturated its take-off's flight while it climbed
// to its waiting point, and its gentler flight was due only in hover, where a catcher never goes;
// attempt 675's (52 ms) was fitted at 54 ms and refused, the grid's best not the error's minimum
// (an infinite interval). Now each is identified within 10 %, and catches.
TEST_CASE("the envelope's hard catchers: a saturated flight flown again at the waiting point, a fit off "
          "the grid's best",
          "[hil][campaign]") {
  const hil::trials::CampaignConfig campaign = envelope_campaign(1);
  const hil::trials::WarmUp warm = hil::trials::warm_up(campaign.plant, campaign.seed);
  for (const int attempt : {287, 675}) {
    const hil::trials::SeriesConfig config = hil::trials::attempt_config(campaign, warm, attempt);
    hil::trials::SeriesRunner runner(config);
    // The attempt flies the warm-up's Fig. 5 throw, not one planned again.
    REQUIRE(warm.fig5_throw);
    CHECK(runner.ground_station().fig5_throw() == warm.fig5_throw);
    const hil::trials::AttemptResult r = runner.run({hil::trials::campaign_attempt_plan()}).front();
    const pa::VehicleId catcher = pa::other_vehicle(pa::VehicleId(static_cast<std::uint8_t>(r.thrower)));
    check_identified(config, runner, attempt, "catcher", catcher, r);
    CHECK(runner.ground_station().equalised_motor_time_constant_s(catcher) ==
          Approx(runner.ground_station().motor_identification(catcher)->identified->time_constant_s));
    CHECK_FALSE(r.vehicle_crashed);
  }
}

// The envelope campaign's (seed 2) attempt 893: the thrower (57.7 ms, inertia gain 1.19) saturated
// its take-off's flight; the person put the pole on while the gentler flight was due, which
// cancelled it, and the thrower balanced at 30 ms, dropped the pole onto the catcher, which
// tumbled. The ground station shows the thrower waiting for the pole only once its identification
// is flown (GroundStation::waiting_for_pole), and the person waits for that.
TEST_CASE("the pole waits for the thrower's identification, its gentler flight included", "[hil][campaign]") {
  const hil::trials::CampaignConfig campaign = envelope_campaign(2);
  const hil::trials::WarmUp warm = hil::trials::warm_up(campaign.plant, campaign.seed);
  hil::trials::SeriesConfig config = hil::trials::attempt_config(campaign, warm, 893);
  std::optional<gs::estimation::IdentificationResult> at_pole;  // the thrower's as the pole went on
  bool placed = false;
  config.on_step = [&](const hil::sil::Arena& arena, const gs::runtime::GroundStation& station) {
    const hil::Contact on = arena.plant().pole_contact();
    if (placed || (on != hil::Contact::vehicle1 && on != hil::Contact::vehicle2)) return;
    placed = true;
    at_pole = station.motor_identification(on == hil::Contact::vehicle1 ? pa::kVehicle1 : pa::kVehicle2);
  };
  hil::trials::SeriesRunner runner(config);
  const hil::trials::AttemptResult r = runner.run({hil::trials::campaign_attempt_plan()}).front();
  const pa::VehicleId thrower(static_cast<std::uint8_t>(r.thrower));
  REQUIRE(placed);
  REQUIRE(at_pole);  // the identification was over when the pole went on: the gentler one's fit
  CHECK(at_pole->identified);
  const double lag_s = config.plant.vehicle.motor_time_constant_s *
                       config.plant.vehicle.motor_time_constant_scale[pa::act_slot(thrower)];
  std::printf("attempt 893 thrower %u: lag %.1f ms, equalised to %.1f ms before the pole; %s\n",
              static_cast<unsigned>(thrower.node()), 1e3 * lag_s,
              1e3 * runner.ground_station().equalised_motor_time_constant_s(thrower),
              std::string(gs::adaptation::to_string(r.outcome)).c_str());
  CHECK(runner.ground_station().equalised_motor_time_constant_s(thrower) == Approx(lag_s).epsilon(0.1));
  CHECK_FALSE(r.vehicle_crashed);
}

// The envelope corner with both vehicles' motors at twice the file's lag, drawn about it (hil
// campaign --attempts 49 --plant hil/config/envelope/motors_60ms.yaml): throwers of 72 and 70 ms
// whose take-off's flight, fitted while they climbed to the throw's origin, was refused (at the
// search's edge; not confident), balanced at 30 ms and dropped the pole, one crashing (4 crashes in
// the 49). The refused flight is flown again once the thrower holds the throw's origin.
TEST_CASE("a thrower's refused identification is flown again at the throw's origin", "[hil][campaign]") {
  const hil::trials::CampaignConfig campaign = campaign_on("hil/config/envelope/motors_60ms.yaml", 1);
  const hil::trials::WarmUp warm = hil::trials::warm_up(campaign.plant, campaign.seed);
  for (const int attempt : {7, 9}) {
    const hil::trials::SeriesConfig config = hil::trials::attempt_config(campaign, warm, attempt);
    hil::trials::SeriesRunner runner(config);
    const hil::trials::AttemptResult r = runner.run({hil::trials::campaign_attempt_plan()}).front();
    check_identified(config, runner, attempt, "thrower", pa::VehicleId(static_cast<std::uint8_t>(r.thrower)),
                     r);
    CHECK(r.outcome == gs::adaptation::ThrowOutcome::caught);
    CHECK_FALSE(r.vehicle_crashed);
  }
}

// The same corner's attempt 14: a 70 ms thrower whose take-off's flight and retry were both refused
// (not confident) was handed the pole, balanced at 30 ms, dropped it, and its attitude diverged
// in hover until the firmware stopped it. The attempt now ends before the pole goes up.
TEST_CASE("a thrower whose motors could not be identified is not handed the pole", "[hil][campaign]") {
  const hil::trials::CampaignConfig campaign = campaign_on("hil/config/envelope/motors_60ms.yaml", 1);
  const hil::trials::WarmUp warm = hil::trials::warm_up(campaign.plant, campaign.seed);
  hil::trials::SeriesConfig config = hil::trials::attempt_config(campaign, warm, 14);
  bool pole_went_up = false;
  config.on_step = [&](const hil::sil::Arena& arena, const gs::runtime::GroundStation&) {
    const hil::Contact on = arena.plant().pole_contact();
    pole_went_up = pole_went_up || on == hil::Contact::vehicle1 || on == hil::Contact::vehicle2;
  };
  hil::trials::SeriesRunner runner(config);
  const hil::trials::AttemptResult r = runner.run({hil::trials::campaign_attempt_plan()}).front();
  const pa::VehicleId thrower(static_cast<std::uint8_t>(r.thrower));
  const auto& id = runner.ground_station().motor_identification(thrower);
  REQUIRE(id);
  INFO("thrower " << int(thrower.node()) << ": " << gs::estimation::refusal_name(id->refusal));
  CHECK_FALSE(id->identified);
  CHECK(r.outcome == gs::adaptation::ThrowOutcome::aborted);
  CHECK(r.abort_reason == "motors_unidentified");
  CHECK_FALSE(pole_went_up);
  CHECK_FALSE(r.vehicle_crashed);
}

TEST_CASE("a stored identification is set on board at arming, before the take-off's own fit") {
  // A store whose vehicle 1 was identified at 50 ms in an earlier run; the default plant's motors
  // lag 30 ms. The ground station sets 50 ms as vehicle 1 arms, so its take-off's fit runs with
  // the equaliser at 50 ms, finds the 30 ms, and sets that back; both are recorded.
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("identification_at_arming_" + std::to_string(::getpid()) + ".sqlite"))
                               .string();
  std::filesystem::remove(path);
  gs::adaptation::IdentificationRecord earlier;
  earlier.vehicle = pa::kVehicle1;
  earlier.time_s = 5.0;
  earlier.result.identified = gs::estimation::MotorIdentification{0.05, 0.048, 0.052, 1.0, 0.02, 0.03, 300};
  gs::adaptation::AdaptationStore::open_or_create(
      path, gs::adaptation::nominal_adaptation_settings(gs::model::PoleParams{}))
      .record_identification(earlier);

  hil::trials::SeriesConfig config;
  config.ground_station.adaptation_store_path = path;
  double equalised_before_fit_s = 0.0;
  config.on_step = [&](const hil::sil::Arena&, const gs::runtime::GroundStation& gs) {
    if (!gs.motor_identification(pa::kVehicle1))
      equalised_before_fit_s = gs.equalised_motor_time_constant_s(pa::kVehicle1);
  };
  {
    hil::trials::SeriesRunner runner(config);
    CHECK(runner.ground_station().kept_motor_identification(pa::kVehicle1)->time_constant_s == 0.05);
    CHECK_FALSE(runner.ground_station().kept_motor_identification(pa::kVehicle2));
    runner.run({});
    runner.hover_for(3.0);
    const auto& id = runner.ground_station().motor_identification(pa::kVehicle1);
    REQUIRE(id);
    REQUIRE(id->identified);
    std::printf("equaliser before the fit %.1f ms; identified %.1f ms; equaliser after %.1f ms\n",
                1e3 * equalised_before_fit_s, 1e3 * id->identified->time_constant_s,
                1e3 * runner.ground_station().equalised_motor_time_constant_s(pa::kVehicle1));
    CHECK(equalised_before_fit_s == 0.05);
    CHECK(id->identified->time_constant_s == Approx(0.03).epsilon(0.1));
    CHECK(runner.ground_station().equalised_motor_time_constant_s(pa::kVehicle1) ==
          id->identified->time_constant_s);
  }
  const gs::adaptation::AdaptationStore store = gs::adaptation::AdaptationStore::open_existing(path);
  CHECK(store.identification_count() == 3);  // the earlier one, then each vehicle's take-off
  CHECK(store.last_accepted_identification(pa::kVehicle1)->id > 1);
  std::filesystem::remove(path);
}
