// A campaign (hil/trials/campaign.hpp): its results depend on the seed alone, whatever the number of
// worker processes; the drawn parameters it records are the plant's own keys (the workers'
// reports: trial_records_test.cpp); its summary adds up the attempts.
#include "hil/trials/campaign.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <string>

#include "hil/plant/randomisation.hpp"
#include "hil/trials/campaign_files.hpp"
#include "hil/trials/trial_config.hpp"

TEST_CASE("the drawn parameters are the plant configuration's keys", "[hil][campaign]") {
  const std::vector<std::string_view> keys = hil::plant_config_keys();
  const hil::PlantConfig drawn = hil::randomised(hil::PlantConfig{}, 3);
  const auto parameters = hil::drawn_parameters(drawn);
  REQUIRE(parameters.size() == 25);
  for (const hil::DrawnParameter& p : parameters) {
    INFO(p.key);
    CHECK(std::find(keys.begin(), keys.end(), p.key) != keys.end());
  }
  CHECK(parameters.front().value == drawn.pole.drag_axial_kgpm2);
  CHECK(parameters.back().value == drawn.radio_loss_probability);
}

TEST_CASE("a campaign is reproducible from its seed whatever the number of workers",
          "[hil][sil][runtime][campaign]") {
  hil::trials::CampaignConfig config;
  config.seed = 4;
  config.attempts = 2;
  config.jobs = 1;
  int reports = 0;
  const auto one =
      hil::trials::run_campaign(config, [&](const auto& done) { reports = static_cast<int>(done.size()); });
  CHECK(reports == 2);
  config.jobs = 2;
  const auto two = hil::trials::run_campaign(config);
  REQUIRE(one.size() == 2);
  REQUIRE(two.size() == 2);
  for (std::size_t i = 0; i < 2; ++i) {
    INFO("attempt " << i + 1);
    CHECK(one[i].result.throw_number == static_cast<int>(i) + 1);
    CHECK(one[i].seed == hil::trials::attempt_seed(4, static_cast<int>(i) + 1));
    CHECK(one[i].result.outcome == two[i].result.outcome);
    CHECK(one[i].result.flight_s == two[i].result.flight_s);
    CHECK(one[i].result.energy_error_J == two[i].result.energy_error_J);
    CHECK(one[i].result.travel_m == two[i].result.travel_m);
    CHECK(one[i].plant.mocap.latency_s == two[i].plant.mocap.latency_s);
    // The attempts differ from each other: each flew its own draw.
  }
  CHECK(one[0].plant.mocap.latency_s != one[1].plant.mocap.latency_s);
}

TEST_CASE("the summary counts the catches, the failures by cause, crashes and switches on the innovations",
          "[hil][campaign]") {
  using hil::trials::AttemptResult;
  std::vector<AttemptResult> results(4);
  for (AttemptResult& r : results) r.outcome = gs::adaptation::ThrowOutcome::caught;
  results[1].outcome = gs::adaptation::ThrowOutcome::dropped;
  results[1].vehicle_crashed = true;
  results[2].innovation_switches = 3;
  results[3].innovation_switches = 7;
  const std::string summary = hil::trials::campaign_summary(results);
  INFO(summary);
  CHECK(summary.rfind("campaign: 3 of 4 attempts caught", 0) == 0);
  CHECK(summary.find("     1  dropped\n") != std::string::npos);
  CHECK(summary.find("vehicles crashed in 1 attempts\n") != std::string::npos);
  CHECK(summary.find("pole mode switches on the innovations: 10 (2.50 an attempt)\n") != std::string::npos);
}
