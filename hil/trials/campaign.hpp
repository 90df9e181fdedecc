// A campaign: many independent attempts to throw and catch, each on a plant drawn anew from its
// configured ranges (randomisation.hpp), flown by the ground-station runtime in the lockstep
// arena and judged on truth (series.hpp), run on several worker processes.
//
// Independent attempts. First a warm-up flies one throw (adapt only) on the nominal plant; what
// the ground station learnt there is where every attempt's ground station starts, as a real one
// would start from its store after calibration flights. Attempt i (1..N) then takes off on the
// plant drawn with attempt_seed(seed, i), its radios losing frames as that plant says
// (trial_config.hpp), and throws once to catch. Nothing else is shared, so the results depend on
// the seed alone, whatever the number of workers.
//
// The attempts run on worker processes (worker_pool.hpp); the parent collects the results in
// order of completion (for the progress line) and returns them in attempt order.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "hil/plant/plant_config.hpp"
#include "hil/trials/series.hpp"

namespace hil::trials {

struct CampaignConfig {
  PlantConfig plant;       // the nominal plant; its randomisation ranges are drawn from
  std::uint64_t seed = 1;  // of the warm-up and of every attempt's draw
  int attempts = 100;
  int jobs = 1;  // worker processes
};

struct CampaignAttempt {
  AttemptResult result;
  std::uint64_t seed = 0;  // the attempt's draw and noise
  PlantConfig plant;       // the plant it flew on
};

// What the ground station learns from one throw (adapt only) on `plant`, flown with `seed`:
// where a campaign's ground stations start.
gs::adaptation::Learnt warm_up(const PlantConfig& plant, std::uint64_t seed);

// Attempt `attempt` (1..N) of the campaign as a series of one throw from `learnt` (the warm-up's):
// what a worker flies, and `hil campaign --replay` again in the open.
SeriesConfig attempt_config(const CampaignConfig& config, const gs::adaptation::Learnt& learnt, int attempt);

// Flies the campaign. `progress` is called in the calling process after each attempt with the
// results so far (in order of completion). Throws std::runtime_error when a worker cannot be
// started or dies without reporting its attempts.
std::vector<CampaignAttempt> run_campaign(
    const CampaignConfig& config,
    const std::function<void(const std::vector<const CampaignAttempt*>& done)>& progress = {});

// The columns of a campaign's throws.csv: `hil fly`'s up to abort_reason, the attempt's seed, then
// the parameters drawn for its plant (drawn_parameters(), keyed as `plant` keys them).
Schema<CampaignAttempt> campaign_throws_columns(const PlantConfig& plant);

}  // namespace hil::trials
