// A campaign in shards (hil/trials/campaign_files.hpp): the shards merged are the one-process
// campaign byte for byte, a shard that did not finish shows up as its missing attempts, and
// shards of another campaign are refused.
#include "hil/trials/campaign_files.hpp"

#include <unistd.h>
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using hil::trials::AttemptResult;
using hil::trials::CampaignConfig;
using hil::trials::CampaignShard;
using hil::trials::ShardFolder;

namespace {

std::string contents(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::vector<AttemptResult> results_of(const std::vector<hil::trials::CampaignAttempt>& attempts) {
  std::vector<AttemptResult> out;
  for (const auto& a : attempts) out.push_back(a.result);
  return out;
}

// Five attempts (shards of 1, 2 and 2), flown once for every test case: whole in `whole`, and
// as shards 1/3..3/3 in `shard_1`..`shard_3`. Few, for the sanitizers' build.
struct Flown {
  fs::path root;
  CampaignConfig config;
  Flown() {
    root = fs::temp_directory_path() / ("campaign_shards_test-" + std::to_string(::getpid()));
    fs::remove_all(root);
    config.seed = 3;
    config.attempts = 5;
    config.jobs = 2;
    std::string error;
    fs::create_directories(root / "whole");
    if (!hil::trials::write_campaign((root / "whole").string(), config,
                                     results_of(hil::trials::run_campaign(config)), error))
      FAIL(error);
    for (int k = 1; k <= 3; ++k) {
      CampaignConfig shard = config;
      shard.shard = CampaignShard{k, 3};
      const fs::path dir = root / ("shard_" + std::to_string(k));
      fs::create_directories(dir);
      if (!hil::trials::write_shard(dir.string(), shard, results_of(hil::trials::run_campaign(shard)), error))
        FAIL(error);
    }
  }
  ~Flown() {
    std::error_code ec;
    fs::remove_all(root, ec);
  }
  ShardFolder read(const std::string& name) const {
    ShardFolder s;
    std::string error;
    if (!hil::trials::read_shard((root / name).string(), s, error)) FAIL(error);
    return s;
  }
};

const Flown& flown() {
  static const Flown f;
  return f;
}

}  // namespace

TEST_CASE("a campaign's shards are contiguous blocks covering every attempt once", "[hil][campaign]") {
  for (int attempts : {1, 7, 10, 1000003}) {
    for (int n : {1, 3, 4, 12}) {
      INFO(attempts << " attempts, " << n << " shards");
      int next = 1;
      for (int k = 1; k <= n; ++k) {
        const hil::trials::AttemptRange r = hil::trials::shard_attempts(attempts, CampaignShard{k, n});
        CHECK(r.first == next);
        CHECK(r.last - r.first + 1 >= attempts / n);
        CHECK(r.last - r.first + 1 <= attempts / n + 1);
        next = r.last + 1;
      }
      CHECK(next == attempts + 1);
    }
  }
  CHECK(hil::trials::parse_shard("2/4")->index == 2);
  for (const char* bad : {"", "0/4", "5/4", "2", "2/", "/4", "-1/4", "2/4x", "a/b", "1/100001", "1/ 4"}) {
    INFO("'" << bad << "'");
    CHECK_FALSE(hil::trials::parse_shard(bad));
  }
  CHECK(hil::trials::describe_missing({3, 4, 5, 9}, 9, 3) == "3 (shard 1/3), 4-5 (shard 2/3), 9 (shard 3/3)");
  CHECK(hil::trials::describe_missing({3, 4, 5, 9}, 9, 0) == "3-5, 9");
}

TEST_CASE("shards merged are the one-process campaign byte for byte", "[hil][sil][runtime][campaign]") {
  const Flown& f = flown();
  hil::trials::MergedCampaign merged;
  std::string error;
  // In any order: the merge puts the attempts in theirs.
  REQUIRE(
      hil::trials::merge_shards({f.read("shard_3"), f.read("shard_1"), f.read("shard_2")}, merged, error));
  CHECK(merged.missing.empty());
  REQUIRE(merged.results.size() == 5);
  fs::create_directories(f.root / "merged");
  REQUIRE(hil::trials::write_campaign((f.root / "merged").string(), merged.config, merged.results, error));
  const std::string whole = contents(f.root / "whole" / "throws.csv");
  CHECK(std::count(whole.begin(), whole.end(), '\n') == 6);
  CHECK(contents(f.root / "merged" / "throws.csv") == whole);
  CHECK(contents(f.root / "merged" / "summary.txt") == contents(f.root / "whole" / "summary.txt"));
  // A shard given twice changes nothing.
  REQUIRE(hil::trials::merge_shards(
      {f.read("shard_1"), f.read("shard_2"), f.read("shard_2"), f.read("shard_3")}, merged, error));
  CHECK(merged.results.size() == 5);
}

TEST_CASE("a shard that did not finish shows up as its missing attempts", "[hil][sil][runtime][campaign]") {
  const Flown& f = flown();
  ShardFolder unfinished;
  std::string error;
  fs::create_directories(f.root / "killed");
  CHECK_FALSE(hil::trials::read_shard((f.root / "killed").string(), unfinished, error));
  CHECK_THAT(error, Catch::Contains("did not finish"));
  hil::trials::MergedCampaign merged;
  REQUIRE(hil::trials::merge_shards({f.read("shard_1"), f.read("shard_3")}, merged, error));
  CHECK(merged.missing == std::vector<int>{2, 3});
  CHECK(hil::trials::describe_missing(merged.missing, 5, 3) == "2-3 (shard 2/3)");

  // A record cut short (a shard's folder damaged after it finished) is named, not read.
  fs::copy(f.root / "shard_2", f.root / "damaged");
  const std::string records = contents(f.root / "damaged" / "attempts.tsv");
  std::ofstream(f.root / "damaged" / "attempts.tsv", std::ios::trunc)
      << records.substr(0, records.size() / 2);
  CHECK_FALSE(hil::trials::read_shard((f.root / "damaged").string(), unfinished, error));
  CHECK_THAT(error, Catch::Contains("attempts.tsv"));
}

TEST_CASE("shards of different campaigns are refused", "[hil][sil][runtime][campaign]") {
  const Flown& f = flown();
  const ShardFolder first = f.read("shard_1");
  // Shard 1's record written as if of another seed, attempt count or plant.
  CampaignConfig other = f.config;
  other.shard = CampaignShard{1, 3};
  std::string why;  // what the refusal names
  SECTION("another seed") {
    other.seed = 4;
    why = "seed 4, not 3";
  }
  SECTION("another number of attempts") {
    other.attempts = 4;  // its shard 1/3 is attempt 1 too
    why = "4 attempts, not 5";
  }
  SECTION("another plant") {
    other.plant.pole.mass_kg *= 1.01;
    why = "plant " + hil::trials::plant_hash(other.plant);
  }
  const fs::path dir = f.root / "other";
  fs::create_directories(dir);
  std::string error;
  REQUIRE(hil::trials::write_shard(dir.string(), other, first.results, error));
  ShardFolder read;
  REQUIRE(hil::trials::read_shard(dir.string(), read, error));
  hil::trials::MergedCampaign merged;
  CHECK_FALSE(hil::trials::merge_shards({f.read("shard_2"), read, f.read("shard_3")}, merged, error));
  CHECK_THAT(error, Catch::Contains("another campaign") && Catch::Contains(why));
}
