// `hil campaign --attempts N --out DIR [--seed S] [--plant FILE] [--jobs J]`: N independent
// attempts to throw and catch, each on a plant drawn anew from the configured ranges, flown in
// the lockstep arena by the ground-station runtime on J worker processes (hil/trials/campaign.hpp).
// Reproducible from S whatever J is. Prints a progress line while it runs and a summary (the
// catch rate with its 95% confidence interval, the failures by cause); writes DIR/throws.csv:
// the columns of `hil fly` and then the drawn parameters of each attempt, and DIR/report.html
// (hil/apps/report.hpp; not with --no-report). With --replay K it flies attempt K alone, in the
// open: the mission log, what the ground station identified beside the plant's truth, and
// DIR/attempt_K.csv, to see why an attempt of a campaign failed. DIR/summary.txt holds the summary.
//
// On a cluster (docs/campaigns.md): `--shard K/N` flies only shard K's block of the attempts, with
// the seeds and warm-up of the whole campaign, and writes DIR as a shard folder
// (hil/trials/campaign_files.hpp); `hil campaign merge --out DIR SHARD_DIR...` joins shards into
// throws.csv, summary.txt and report.html, byte for byte what one process writes. It names the
// attempts no shard holds (exit 1, nothing written) and refuses shards of another campaign (exit 2).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "hil/apps/batch_options.hpp"
#include "hil/apps/commands.hpp"
#include "hil/apps/flight_output.hpp"
#include "hil/apps/report.hpp"
#include "hil/plant/plant_config.hpp"
#include "hil/plant/randomisation.hpp"
#include "hil/trials/campaign.hpp"
#include "hil/trials/campaign_files.hpp"
#include "pa/command_line.hpp"

namespace hil::apps {
namespace {

constexpr const char* kUsage =
    "usage: hil campaign --attempts N --out DIR [--seed S] [--plant FILE] [--jobs J] [--no-report] [--replay K]\n"
    "                    [--shard K/N]\n"
    "       hil campaign merge --out DIR [--no-report] SHARD_DIR...";

constexpr const char* kMergeUsage = "usage: hil campaign merge --out DIR [--no-report] SHARD_DIR...";

// The summary as both a run and a merge print it: the statistics (summary.txt) and how they were made.
void print_summary(const std::vector<trials::AttemptResult>& results, const std::string& how) {
  std::printf("%s  %s\n", trials::campaign_summary(results).c_str(), how.c_str());
  std::fflush(stdout);
}

// `hil campaign merge`: argv[0] is "merge".
int cmd_merge(int argc, char** argv) {
  std::string out_dir;
  std::vector<std::string> shard_dirs;
  bool no_report = false;
  CLI::App app("", "hil campaign merge");
  pa::cli::describe(app, kMergeUsage,
                    "Joins the shard folders of one campaign (hil campaign --shard K/N --out SHARD_DIR)\n"
                    "into DIR/throws.csv, DIR/summary.txt and DIR/report.html, as one process would have\n"
                    "written them. Names the attempts no shard holds (exit 1: fly those shards again) and\n"
                    "refuses shards of different campaigns (exit 2).");
  app.add_option("--out", out_dir, "write DIR/throws.csv, DIR/summary.txt and DIR/report.html")
      ->type_name("DIR")
      ->required();
  app.add_flag("--no-report", no_report, "the CSV file and the summary only, no report.html");
  app.add_option("SHARD_DIR", shard_dirs, "the shards' folders")->type_name("SHARD_DIR")->required();
  if (const std::optional<int> code = pa::cli::parse(app, argc, argv, std::cout, std::cerr)) return *code;

  std::vector<trials::ShardFolder> shards;
  for (const std::string& dir : shard_dirs) {
    trials::ShardFolder shard;
    std::string error;
    if (!trials::read_shard(dir, shard, error)) {
      // A shard that died leaves a folder without a manifest: its attempts count as missing.
      std::cerr << "hil campaign merge: " << error << "; its attempts count as missing\n";
      continue;
    }
    shards.push_back(std::move(shard));
  }
  if (shards.empty()) {
    std::cerr << "hil campaign merge: no finished shard among the " << shard_dirs.size()
              << " folders given\n";
    return 1;
  }
  trials::MergedCampaign merged;
  std::string error;
  if (!trials::merge_shards(shards, merged, error)) {
    std::cerr << "hil campaign merge: " << error << "\n";
    return 2;
  }
  if (!merged.missing.empty()) {
    // Name the shards to fly again when every shard given was split the same way.
    int n_ways = shards.front().config.shard.count;
    for (const trials::ShardFolder& s : shards) {
      if (s.config.shard.count != n_ways) n_ways = 0;
    }
    std::cerr
        << "hil campaign merge: " << merged.missing.size() << " of " << merged.config.attempts
        << " attempts missing: " << trials::describe_missing(merged.missing, merged.config.attempts, n_ways)
        << "\nhil campaign merge: fly those shards again (hil campaign --shard K/N with the same --attempts, "
        << "--seed " << merged.config.seed << " and plant) and merge again; nothing written\n";
    return 1;
  }
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec) {
    std::cerr << "hil campaign merge: cannot create '" << out_dir << "': " << ec.message() << "\n";
    return 1;
  }
  if (!trials::write_campaign(out_dir, merged.config, merged.results, error)) {
    std::cerr << "hil campaign merge: " << error << "\n";
    return 1;
  }
  print_summary(merged.results, "seed " + std::to_string(merged.config.seed) + ", merged from " +
                                    std::to_string(shards.size()) + " shards; " + out_dir + "/throws.csv");
  if (!no_report) make_report(out_dir, "hil campaign merge");
  return 0;
}

// Flies attempt `k` of the campaign in this process, its mission log printed.
int replay(const trials::CampaignConfig& campaign, int k, const std::string& out_dir) {
  trials::SeriesConfig config =
      trials::attempt_config(campaign, trials::warm_up(campaign.plant, campaign.seed), k);
  config.record_time_series = true;
  config.log = [](const std::string& line) { std::printf("%s\n", line.c_str()); };
  trials::SeriesRunner runner(config);
  const trials::AttemptResult r = runner.run({trials::campaign_attempt_plan()}).front();
  std::printf("attempt %d (seed %llu): %s, flight %.3f s, energy error %.5f J%s%s%s\n", k,
              static_cast<unsigned long long>(config.seed),
              std::string(gs::adaptation::to_string(r.outcome)).c_str(), r.flight_s, r.energy_error_J,
              r.abort_reason.empty() ? "" : ", ", r.abort_reason.c_str(),
              r.vehicle_crashed ? " (vehicle crashed)" : "");
  print_identification(runner.ground_station(), runner.arena().plant());
  // An attempt whose take-off failed never flew: nothing was recorded.
  if (runner.time_series().empty()) {
    std::printf("no time series: the attempt was not flown\n");
    return 0;
  }
  const std::string path = out_dir + "/attempt_" + std::to_string(k) + ".csv";
  write_time_series(path, runner.time_series().front());
  std::printf("wrote %s\n", path.c_str());
  return 0;
}

}  // namespace

int cmd_campaign(int argc, char** argv) {
  if (argc >= 2 && std::string(argv[1]) == "merge") return cmd_merge(argc - 1, argv + 1);
  std::uint64_t attempts = 0;
  bool no_report = false;
  CLI::App app("", "hil campaign");
  pa::cli::describe(app, kUsage,
                    "Flies N independent attempts to throw and catch, each on a plant drawn anew from its\n"
                    "ranges, on J worker processes; reproducible from the seed whatever J is. Writes\n"
                    "DIR/throws.csv (the columns of hil fly and the drawn parameters), DIR/summary.txt and\n"
                    "DIR/report.html. With --shard K/N only shard K's block of the attempts, DIR a shard\n"
                    "folder for hil campaign merge (docs/campaigns.md).");
  app.add_option("--attempts", attempts, "number of attempts")
      ->type_name("N")
      ->required()
      ->check(pa::cli::count(1, 1000000, "needs a count 1..1000000"));
  BatchOptions batch;
  add_batch_options(app, batch, "throws.csv", "the draws and the noise");
  app.add_flag("--no-report", no_report, "the CSV file only, no report.html");
  std::uint64_t replay_attempt = 0;
  app.add_option("--replay", replay_attempt,
                 "fly attempt K alone, its mission log printed; writes DIR/attempt_K.csv")
      ->type_name("K")
      ->check(pa::cli::count(1, 1000000, "needs an attempt's number 1..1000000"));
  std::string shard_text;
  app.add_option("--shard", shard_text,
                 "fly only shard K of N (its block of the attempts) and write DIR as a shard folder")
      ->type_name("K/N")
      ->check(CLI::Validator(
          [](std::string& text) {
            return trials::parse_shard(text) ? std::string()
                                             : "needs K/N with 1 <= K <= N <= 100000, got '" + text + "'";
          },
          ""));
  if (const std::optional<int> code = pa::cli::parse(app, argc, argv, std::cout, std::cerr)) return *code;

  trials::CampaignConfig config;
  if (const std::optional<int> code = prepare_batch("hil campaign", batch, config.plant, config.jobs))
    return *code;
  const std::string& out_dir = batch.out_dir;
  config.seed = batch.seed;
  config.attempts = static_cast<int>(attempts);
  if (!shard_text.empty()) config.shard = *trials::parse_shard(shard_text);
  if (replay_attempt > 0) {
    if (replay_attempt > attempts) {
      std::cerr << "hil campaign: --replay " << replay_attempt << " is not an attempt of " << attempts
                << "\n";
      return 2;
    }
    return replay(config, static_cast<int>(replay_attempt), out_dir);
  }

  const trials::AttemptRange range = trials::shard_attempts(config.attempts, config.shard);
  const int share = range.last - range.first + 1;
  const auto start = std::chrono::steady_clock::now();
  std::vector<trials::CampaignAttempt> results;
  try {
    results = trials::run_campaign(config, [&](const std::vector<const trials::CampaignAttempt*>& done) {
      const int caught =
          static_cast<int>(std::count_if(done.begin(), done.end(), [](const trials::CampaignAttempt* a) {
            return a->result.outcome == gs::adaptation::ThrowOutcome::caught;
          }));
      const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      std::fprintf(stderr, "\rhil campaign: %zu/%d attempts, %d caught (%.1f%%), %.0f s", done.size(), share,
                   caught, 100.0 * caught / static_cast<double>(done.size()), elapsed);
      std::fflush(stderr);
    });
  } catch (const std::exception& e) {
    std::cerr << "\nhil campaign: " << e.what() << "\n";
    return 1;
  }
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::fprintf(stderr, "\n");

  std::vector<trials::AttemptResult> flown;
  flown.reserve(results.size());
  for (const trials::CampaignAttempt& a : results) flown.push_back(a.result);
  std::string error;
  if (!shard_text.empty()) {
    if (!trials::write_shard(out_dir, config, flown, error)) {
      std::cerr << "hil campaign: " << error << "\n";
      return 1;
    }
    const long caught = std::count_if(flown.begin(), flown.end(), [](const trials::AttemptResult& r) {
      return r.outcome == gs::adaptation::ThrowOutcome::caught;
    });
    // More shards than attempts leaves some empty: harmless, merged like any other.
    const std::string flew = share < 1
                                 ? "no attempts"
                                 : "attempts " + std::to_string(range.first) + "-" +
                                       std::to_string(range.last) + ", " + std::to_string(caught) + " caught";
    std::printf(
        "shard %s of a campaign of %d attempts (seed %llu): %s; %d worker processes, wall time %.1f s; %s\n",
        shard_text.c_str(), config.attempts, static_cast<unsigned long long>(config.seed), flew.c_str(),
        config.jobs, wall_s, out_dir.c_str());
    return 0;
  }
  if (!trials::write_campaign(out_dir, config, flown, error)) {
    std::cerr << "hil campaign: " << error << "\n";
    return 1;
  }
  char how[160];
  std::snprintf(how, sizeof how, "seed %llu, %d worker processes, wall time %.1f s; ",
                static_cast<unsigned long long>(config.seed), config.jobs, wall_s);
  print_summary(flown, how + out_dir + "/throws.csv");
  if (!no_report) make_report(out_dir, "hil campaign");
  return 0;
}

}  // namespace hil::apps
