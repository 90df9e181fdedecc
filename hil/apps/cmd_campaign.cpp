// `hil campaign --attempts N --out DIR [--seed S] [--plant FILE] [--jobs J]`: N independent
// attempts to throw and catch, each on a plant drawn anew from the configured ranges, flown in
// the lockstep arena by the ground-station runtime on J worker processes (hil/trials/campaign.hpp).
// Reproducible from S whatever J is. Prints a progress line while it runs and a summary (the
// catch rate with its 95% confidence interval, the failures by cause); writes DIR/throws.csv:
// the columns of `hil fly` and then the drawn parameters of each attempt, and DIR/report.html
// (hil/apps/report.hpp; not with --no-report). With --replay K it flies attempt K alone, in the
// open: the mission log, what the ground station identified beside the plant's truth, and
// DIR/attempt_K.csv, to see why an attempt of a campaign failed.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
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
#include "pa/command_line.hpp"

namespace hil::apps {
namespace {

constexpr const char* kUsage =
    "usage: hil campaign --attempts N --out DIR [--seed S] [--plant FILE] [--jobs J] [--no-report] [--replay K]";

// Wilson's score interval for k successes in n trials at 95%: unlike the normal approximation
// it stays inside [0, 1] and is honest near 100%, where a campaign's rate lies.
std::pair<double, double> wilson95(int k, int n) {
  const double z = 1.959964;
  const double p = static_cast<double>(k) / n;
  const double d = 1.0 + z * z / n;
  const double centre = (p + z * z / (2.0 * n)) / d;
  const double half = z * std::sqrt(p * (1.0 - p) / n + z * z / (4.0 * n * n)) / d;
  return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

// Flies attempt `k` of the campaign in this process, its mission log printed.
int replay(const trials::CampaignConfig& campaign, int k, const std::string& out_dir) {
  trials::SeriesConfig config =
      trials::attempt_config(campaign, trials::warm_up(campaign.plant, campaign.seed), k);
  config.record_time_series = true;
  config.log = [](const std::string& line) { std::printf("%s\n", line.c_str()); };
  trials::SeriesRunner runner(config);
  const trials::AttemptResult r = runner.run({trials::AttemptPlan{}}).front();
  std::printf("attempt %d (seed %llu): %s, flight %.3f s, energy error %.5f J%s%s%s\n", k,
              static_cast<unsigned long long>(config.seed),
              std::string(gs::adaptation::to_string(r.outcome)).c_str(), r.flight_s, r.energy_error_J,
              r.abort_reason.empty() ? "" : ", ", r.abort_reason.c_str(),
              r.vehicle_crashed ? " (vehicle crashed)" : "");
  print_identification(runner.ground_station(), runner.arena().plant());
  const std::string path = out_dir + "/attempt_" + std::to_string(k) + ".csv";
  write_time_series(path, runner.time_series().front());
  std::printf("wrote %s\n", path.c_str());
  return 0;
}

}  // namespace

int cmd_campaign(int argc, char** argv) {
  std::uint64_t attempts = 0;
  bool no_report = false;
  CLI::App app("", "hil campaign");
  pa::cli::describe(app, kUsage,
                    "Flies N independent attempts to throw and catch, each on a plant drawn anew from its\n"
                    "ranges, on J worker processes; reproducible from the seed whatever J is. Writes\n"
                    "DIR/throws.csv (the columns of hil fly and the drawn parameters) and DIR/report.html.");
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
      ->type_name("K");
  if (const std::optional<int> code = pa::cli::parse(app, argc, argv, std::cout, std::cerr)) return *code;

  trials::CampaignConfig config;
  if (const std::optional<int> code = prepare_batch("hil campaign", batch, config.plant, config.jobs))
    return *code;
  const std::string& out_dir = batch.out_dir;
  config.seed = batch.seed;
  config.attempts = static_cast<int>(attempts);
  if (replay_attempt > 0) {
    if (replay_attempt > attempts) {
      std::cerr << "hil campaign: --replay " << replay_attempt << " is not an attempt of " << attempts
                << "\n";
      return 2;
    }
    return replay(config, static_cast<int>(replay_attempt), out_dir);
  }

  const auto start = std::chrono::steady_clock::now();
  std::vector<trials::CampaignAttempt> results;
  try {
    results = trials::run_campaign(config, [&](const std::vector<const trials::CampaignAttempt*>& done) {
      const int caught =
          static_cast<int>(std::count_if(done.begin(), done.end(), [](const trials::CampaignAttempt* a) {
            return a->result.outcome == gs::adaptation::ThrowOutcome::caught;
          }));
      const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      std::fprintf(stderr, "\rhil campaign: %zu/%d attempts, %d caught (%.1f%%), %.0f s", done.size(),
                   config.attempts, caught, 100.0 * caught / static_cast<double>(done.size()), elapsed);
      std::fflush(stderr);
    });
  } catch (const std::exception& e) {
    std::cerr << "\nhil campaign: " << e.what() << "\n";
    return 1;
  }
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::fprintf(stderr, "\n");

  std::ofstream csv(out_dir + "/throws.csv");
  trials::write_csv(csv, trials::campaign_throws_columns(results.front().plant), results);
  std::map<std::string, int> failures;
  int caught = 0, crashed = 0;
  for (const trials::CampaignAttempt& a : results) {
    const trials::AttemptResult& r = a.result;
    if (r.outcome == gs::adaptation::ThrowOutcome::caught) {
      ++caught;
    } else {
      const std::string outcome(gs::adaptation::to_string(r.outcome));
      ++failures[r.abort_reason.empty() ? outcome : outcome + " (" + r.abort_reason + ")"];
    }
    if (r.vehicle_crashed) ++crashed;
  }
  csv.close();
  if (!csv) {
    std::cerr << "hil campaign: cannot write '" << out_dir << "/throws.csv'\n";
    return 1;
  }
  const auto [lo, hi] = wilson95(caught, config.attempts);
  std::printf(
      "campaign: %d of %d attempts caught and balanced again for 3 s: %.1f%% (95%% interval %.1f-%.1f%%)\n",
      caught, config.attempts, 100.0 * caught / config.attempts, 100.0 * lo, 100.0 * hi);
  for (const auto& [cause, n] : failures) std::printf("  %4d  %s\n", n, cause.c_str());
  std::printf("  vehicles crashed in %d attempts\n", crashed);
  std::printf("  seed %llu, %d worker processes, wall time %.1f s; %s/throws.csv\n",
              static_cast<unsigned long long>(config.seed), config.jobs, wall_s, out_dir.c_str());
  std::fflush(stdout);
  if (!no_report) make_report(out_dir, "hil campaign");
  return 0;
}

}  // namespace hil::apps
