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
//
// Shards. Shard K of N flies only its block of the attempts (shard_attempts()), with the same
// seeds and the same warm-up as the whole campaign, so that the shards' results together are the
// whole campaign's, attempt for attempt; campaign_files.hpp writes a shard and merges shards.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hil/plant/plant_config.hpp"
#include "hil/trials/series.hpp"

namespace hil::trials {

// Shard `index` of `count` (1..count); 1 of 1 is the whole campaign.
struct CampaignShard {
  int index = 1;
  int count = 1;
};

struct CampaignConfig {
  PlantConfig plant;       // the nominal plant; its randomisation ranges are drawn from
  std::uint64_t seed = 1;  // of the warm-up and of every attempt's draw
  int attempts = 100;
  int jobs = 1;         // worker processes
  CampaignShard shard;  // the share of the attempts flown here
};

// Attempts first..last (1-based, inclusive; empty when last < first).
struct AttemptRange {
  int first = 1;
  int last = 0;
};

// The attempts shard K of N flies: the K-th of N contiguous blocks covering 1..attempts, their
// sizes differing by at most one (a block is empty when N > attempts).
AttemptRange shard_attempts(int attempts, CampaignShard shard);

// "K/N" as a shard of 1 <= K <= N <= 100000; nullopt for any other text.
std::optional<CampaignShard> parse_shard(const std::string& text);

struct CampaignAttempt {
  AttemptResult result;
  std::uint64_t seed = 0;  // the attempt's draw and noise
  PlantConfig plant;       // the plant it flew on
};

// What the ground station learns from one throw (adapt only) on `plant`, flown with `seed`:
// where a campaign's ground stations start; and the Fig. 5 throw it planned, which theirs (of the
// same configuration) fly without planning it again.
struct WarmUp {
  gs::adaptation::Learnt learnt;
  std::shared_ptr<const gs::planning::Fig5Throw> fig5_throw;
};
WarmUp warm_up(const PlantConfig& plant, std::uint64_t seed);

// The one attempt each campaign attempt flies: the person places the pole, either vehicle may
// throw and the one with the higher thrust ceiling does, as an arena would choose
// (GroundStation::stronger_thrower); the other catches.
AttemptPlan campaign_attempt_plan();

// Attempt `attempt` (1..N) of the campaign as a series of one throw from the warm-up's state:
// what a worker flies, and `hil campaign --replay` again in the open.
SeriesConfig attempt_config(const CampaignConfig& config, const WarmUp& warm, int attempt);

// Flies the campaign's share config.shard (all of it by default), returned in attempt order.
// `progress` is called in the calling process after each attempt with the results so far (in
// order of completion). Throws std::runtime_error for a shard that is not K of N with
// 1 <= K <= N, when a worker cannot be started or dies without reporting its attempts.
std::vector<CampaignAttempt> run_campaign(
    const CampaignConfig& config,
    const std::function<void(const std::vector<const CampaignAttempt*>& done)>& progress = {});

// The columns of a campaign's throws.csv: `hil fly`'s up to abort_reason, the attempt's seed, then
// the parameters drawn for its plant (drawn_parameters(), keyed as `plant` keys them).
Schema<CampaignAttempt> campaign_throws_columns(const PlantConfig& plant);

}  // namespace hil::trials
