// What a campaign writes (campaign.hpp), whole or in shards, and the merge of shards into the
// whole: one writer for both, so that merged shards are the one-process campaign byte for byte.
//
// A campaign's folder: throws.csv (a row per attempt: campaign_throws_columns()) and summary.txt
// (campaign_summary(): the catch rate with its interval, the failures by cause, the crashes, the
// ground station's pole mode switches on the innovations).
//
// A shard's folder (`hil campaign --shard K/N --out DIR`), what the merge needs and no more:
//   plant.yaml    the nominal plant, canonical (format_plant_config(): every value exact)
//   attempts.tsv  a line per attempt of the shard, every field exact (encode_result()), in order
//   shard.txt     the manifest, written last (its presence says the shard finished): the
//                 campaign's identity (seed, attempts, the plant's hash, the record's fields)
//                 and the shard's (K/N, its first and last attempt)
// The CSV rows are made again at the merge from the exact records and the plant drawn anew with
// each attempt's seed, by the writer the one-process campaign uses: a row cannot differ.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "hil/trials/campaign.hpp"

namespace hil::trials {

// The statistics of a campaign's results (lines ended by '\n'): what summary.txt holds and what
// `hil campaign` prints, for a run in one process and for merged shards alike.
std::string campaign_summary(const std::vector<AttemptResult>& results);

// The 64-bit FNV-1a hash of the canonical text of `plant`, as 16 hex digits: the plant in a
// campaign's identity, whatever file (or none) it was loaded from.
std::string plant_hash(const PlantConfig& plant);

// Writes DIR/throws.csv and DIR/summary.txt for `results` (attempts 1..config.attempts, in
// order), the plants drawn anew from config.plant and config.seed. False with `error` when a
// file cannot be written.
bool write_campaign(const std::string& dir, const CampaignConfig& config,
                    const std::vector<AttemptResult>& results, std::string& error);

// Writes shard config.shard's folder DIR from its `results` (those of shard_attempts(), in order).
// Each file goes to a temporary name first and the manifest last, so a shard killed while
// writing leaves no manifest. False with `error` when a file cannot be written.
bool write_shard(const std::string& dir, const CampaignConfig& config,
                 const std::vector<AttemptResult>& results, std::string& error);

// A finished shard's folder as read back.
struct ShardFolder {
  std::string dir;
  CampaignConfig config;  // seed, attempts, shard and plant (jobs is not recorded)
  std::string plant_hash;
  AttemptRange range;
  std::vector<AttemptResult> results;  // range.first..range.last
};

// Reads DIR. False with `error` (naming the file and what is wrong) for a folder without a
// manifest (a shard that did not finish), a manifest or record that does not read, a record
// schema other than this build's, or a plant.yaml whose hash is not the manifest's.
bool read_shard(const std::string& dir, ShardFolder& shard, std::string& error);

struct MergedCampaign {
  CampaignConfig config;               // of the shards' campaign (shard 1/1)
  std::vector<AttemptResult> results;  // attempts 1..attempts; complete when nothing is missing
  std::vector<int> missing;            // the attempts no shard holds, ascending
};

// Joins `shards`. False with `error` when they are not of one campaign (seed, attempts, plant),
// naming the shard and the difference, or when two hold one attempt with different results.
// Missing attempts are not an error: `merged.missing` lists them.
bool merge_shards(const std::vector<ShardFolder>& shards, MergedCampaign& merged, std::string& error);

// The missing attempts as ranges, each with the shard K/N that flies it when the shards given
// were all split N ways ("4-6 (shard 2/3), 9 (shard 3/3)"); n_ways 0: not named.
std::string describe_missing(const std::vector<int>& missing, int attempts, int n_ways);

}  // namespace hil::trials
