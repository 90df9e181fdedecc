// Setpoint-stream cuts (hil/trials/cuts.hpp): cut at drawn instants of every phase of the mission,
// both vehicles reach the firmware's levelled hover within 25 ms of their last setpoint, level
// on truth, and land with the motors off without crashing; the cuts depend on the seed alone,
// whatever the number of workers (the workers' reports: trial_records_test.cpp).
#include "hil/trials/cuts.hpp"

#include <catch2/catch.hpp>

#include <string>
#include <vector>

TEST_CASE("cut in every phase, both vehicles level within 25 ms and land with the motors off",
          "[hil][cuts]") {
  hil::trials::CutsConfig config;
  config.seed = 3;
  config.cuts = 20;
  config.cuts_per_mission = 10;
  config.jobs = 2;
  const std::vector<hil::trials::CutResult> cuts = hil::trials::run_cuts(config);
  REQUIRE(cuts.size() == 20);
  std::vector<int> per_phase(hil::trials::kCutPhaseCount, 0);
  for (const hil::trials::CutResult& r : cuts) {
    ++per_phase[static_cast<std::size_t>(r.phase)];
    for (const hil::trials::VehicleCut& c : r.vehicles) {
      INFO("cut " << r.cut << " at " << r.t_cut_s << " s in " << hil::trials::cut_phase_name(r.phase) << ": "
                  << c.failure);
      CHECK(c.mode_at_cut == "flying");
      CHECK(c.failsafe_after_s >= 0.0);
      CHECK(c.failsafe_after_s <= config.limits.failsafe_within_s);
      CHECK(c.levelled_after_s >= c.failsafe_after_s);
      CHECK(c.landed);
      CHECK(c.final_mode == "landed");
      CHECK(c.motors_off);
      CHECK_FALSE(c.crashed);
      CHECK(c.touchdown_speed_mps > 0.0);
      CHECK(c.touchdown_speed_mps < config.limits.crash_speed_mps);
      CHECK(c.failure.empty());
    }
  }
  for (int n : per_phase) CHECK(n == 4);  // the mission flew every phase

  // The same cuts on one worker.
  config.jobs = 1;
  const std::vector<hil::trials::CutResult> again = hil::trials::run_cuts(config);
  REQUIRE(again.size() == cuts.size());
  for (std::size_t i = 0; i < cuts.size(); ++i) {
    CHECK(again[i].t_cut_s == cuts[i].t_cut_s);
    CHECK(again[i].phase == cuts[i].phase);
    CHECK(again[i].vehicles[0].touchdown_speed_mps == cuts[i].vehicles[0].touchdown_speed_mps);
    CHECK(again[i].vehicles[1].touchdown_after_s == cuts[i].vehicles[1].touchdown_after_s);
  }
}
