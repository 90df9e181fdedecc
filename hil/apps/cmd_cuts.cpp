// `hil cuts --cuts N --out DIR [--seed S] [--plant FILE] [--jobs J] [--per-mission K]`: N cuts
// of the ground station's setpoint stream at drawn instants of the closed-loop mission (hover,
// balance, throw, catch manoeuvre, after the catch), each judged on truth until both vehicles
// have landed (hil/trials/cuts.hpp). Reproducible from S (and K) whatever J is. Writes DIR/cuts.csv,
// one row per vehicle per cut, and prints a summary: failures by cause and by phase, the times
// to the failsafe and to levelled, and the touchdown speeds' distribution with a histogram.
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
#include "hil/plant/plant_config.hpp"
#include "hil/trials/cuts.hpp"
#include "pa/command_line.hpp"

namespace hil::apps {
namespace {

constexpr const char* kUsage =
    "usage: hil cuts --cuts N --out DIR [--seed S] [--plant FILE] [--jobs J] [--per-mission K]";
constexpr double kDeg = 180.0 / M_PI;

// The nearest-rank percentile of sorted values.
double percentile(const std::vector<double>& sorted, double p) {
  const auto rank = static_cast<std::size_t>(std::ceil(p / 100.0 * static_cast<double>(sorted.size())));
  return sorted[std::min(sorted.size() - 1, rank == 0 ? 0 : rank - 1)];
}

void print_distribution(const char* what, std::vector<double> values, double scale, const char* unit) {
  if (values.empty()) {
    std::printf("  %s: none\n", what);
    return;
  }
  std::sort(values.begin(), values.end());
  std::printf("  %s (%zu): min %.3f, p1 %.3f, p5 %.3f, p50 %.3f, p95 %.3f, p99 %.3f, max %.3f %s\n", what,
              values.size(), scale * values.front(), scale * percentile(values, 1),
              scale * percentile(values, 5), scale * percentile(values, 50), scale * percentile(values, 95),
              scale * percentile(values, 99), scale * values.back(), unit);
}

// Touchdown speeds in bins of `bin` m/s up to `top`, the faster ones in one line; bars scaled to
// the fullest bin.
void print_histogram(const std::vector<double>& values, double bin, double top) {
  if (values.empty()) return;
  const double lo = *std::min_element(values.begin(), values.end());
  const double hi = std::min(top, *std::max_element(values.begin(), values.end()));
  const long first = static_cast<long>(std::floor(std::min(lo, hi) / bin));
  const long last = static_cast<long>(std::floor(hi / bin));
  std::vector<int> counts(static_cast<std::size_t>(last - first + 1), 0);
  int above = 0;
  for (double v : values) {
    if (v >= top) ++above;
    else ++counts[static_cast<std::size_t>(static_cast<long>(std::floor(v / bin)) - first)];
  }
  const int most = std::max(above, *std::max_element(counts.begin(), counts.end()));
  const auto bar = [&](int n) {
    return std::string(static_cast<std::size_t>(std::lround(50.0 * n / most)), '#');
  };
  for (std::size_t i = 0; i < counts.size(); ++i) {
    const double from = static_cast<double>(first + static_cast<long>(i)) * bin;
    std::printf("    %.2f-%.2f m/s %6d %s\n", from, from + bin, counts[i], bar(counts[i]).c_str());
  }
  if (above > 0) std::printf("    >= %.2f m/s   %6d %s\n", top, above, bar(above).c_str());
}

}  // namespace

int cmd_cuts(int argc, char** argv) {
  std::uint64_t cuts = 0, per_mission = 50;
  CLI::App app("", "hil cuts");
  pa::cli::describe(app, kUsage,
                    "Cuts the ground station's setpoint stream to both vehicles at N instants drawn over\n"
                    "the closed-loop mission (hover, balance, throw, catch manoeuvre, after the catch) and\n"
                    "judges the firmware's failsafe on truth until both have landed; reproducible from\n"
                    "the seed whatever J is. Writes DIR/cuts.csv (one row per vehicle per cut).");
  app.add_option("--cuts", cuts, "number of cuts")
      ->type_name("N")
      ->required()
      ->check(pa::cli::count(1, 1000000, "needs a count 1..1000000"));
  BatchOptions batch;
  add_batch_options(app, batch, "cuts.csv", "the missions and the cut instants");
  app.add_option("--per-mission", per_mission, "cuts forked from one mission (default 50)")
      ->type_name("K")
      ->check(pa::cli::count(1, 100000, "needs a count 1..100000"));
  if (const std::optional<int> code = pa::cli::parse(app, argc, argv, std::cout, std::cerr)) return *code;

  trials::CutsConfig config;
  if (const std::optional<int> code = prepare_batch("hil cuts", batch, config.plant, config.jobs))
    return *code;
  const std::string& out_dir = batch.out_dir;
  config.seed = batch.seed;
  config.cuts = static_cast<int>(cuts);
  config.cuts_per_mission = static_cast<int>(per_mission);

  const auto start = std::chrono::steady_clock::now();
  std::vector<trials::CutResult> results;
  try {
    results = trials::run_cuts(config, [&](int done) {
      const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      std::fprintf(stderr, "\rhil cuts: %d/%d cuts, %.0f s", done, config.cuts, elapsed);
      std::fflush(stderr);
    });
  } catch (const std::exception& e) {
    std::cerr << "\nhil cuts: " << e.what() << "\n";
    return 1;
  }
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::fprintf(stderr, "\n");

  std::ofstream csv(out_dir + "/cuts.csv");
  const trials::Schema<trials::CutRow> columns = trials::cuts_csv_columns();
  csv << trials::csv_header(columns) << "\n";
  const trials::CutLimits& lim = config.limits;
  std::map<std::string, int> causes;
  std::map<std::string, std::pair<int, int>> phases;  // cuts, cuts with a failure
  std::vector<double> speeds, failsafe_s, levelled_s;
  int failed_cuts = 0, vehicles_failed = 0, levelled_in_limit = 0, crashed = 0, killed = 0, lost_before = 0;
  for (const trials::CutResult& r : results) {
    bool failed = false;
    for (const pa::VehicleId v : pa::kActVehicles) {
      const trials::VehicleCut& c = r.vehicles[pa::act_slot(v)];
      csv << trials::csv_row(columns, trials::CutRow{&r, v}) << "\n";
      if (c.touchdown_speed_mps >= 0.0) speeds.push_back(c.touchdown_speed_mps);
      if (c.failsafe_after_s >= 0.0) failsafe_s.push_back(c.failsafe_after_s);
      if (c.levelled_after_s >= 0.0) levelled_s.push_back(c.levelled_after_s);
      if (c.levelled_after_s >= 0.0 && c.levelled_after_s <= lim.failsafe_within_s + 1e-9)
        ++levelled_in_limit;
      if (c.crashed) ++crashed;
      if (c.final_mode == "killed") ++killed;
      if (!c.failure.empty()) {
        failed = true;
        ++vehicles_failed;
        ++causes[c.failure];
        if (c.failure.rfind(trials::kLostBeforeCut, 0) == 0) ++lost_before;
      }
    }
    auto& p = phases[std::string(trials::cut_phase_name(r.phase))];
    ++p.first;
    if (failed) {
      ++p.second;
      ++failed_cuts;
    }
  }
  csv.close();
  if (!csv) {
    std::cerr << "hil cuts: cannot write '" << out_dir << "/cuts.csv'\n";
    return 1;
  }
  const int vehicles = 2 * config.cuts;
  std::printf(
      "cuts: %d cuts, %d vehicles: %d vehicles failed (in %d cuts), %d crashed; %d of the failed had been\n"
      "  lost by the mission flown uncut before their cut (%s: tilted past 60 deg)\n",
      config.cuts, vehicles, vehicles_failed, failed_cuts, crashed, lost_before,
      std::string(trials::kLostBeforeCut).c_str());
  std::printf(
      "  pass: firmware levelled on board (its hold) within %.0f ms of its last setpoint, then levelled on truth\n"
      "  (tilt < %.0f deg, body rates < %.2f rad/s), landed with the motors off within %.0f s, no\n"
      "  touchdown faster than %.2f m/s or tilted more than %.0f deg\n",
      1e3 * lim.failsafe_within_s, kDeg * lim.level_tilt_rad, lim.level_rate_radps, lim.land_within_s,
      lim.crash_speed_mps, kDeg * lim.crash_tilt_rad);
  for (const auto& [cause, n] : causes) std::printf("  %6d vehicles  %s\n", n, cause.c_str());
  std::printf(
      "  firmware ended in killed (motors off; its impact detector classed the touchdown or an impact\n"
      "  as a crash) for %d vehicles; judged on truth above\n",
      killed);
  std::printf("  by phase (cuts, cuts with a failure):");
  for (int p = 0; p < trials::kCutPhaseCount; ++p) {
    const std::string name(trials::cut_phase_name(static_cast<trials::CutPhase>(p)));
    std::printf(" %s %d/%d", name.c_str(), phases[name].first, phases[name].second);
  }
  std::printf("\n");
  print_distribution("last setpoint -> hold (levelled on board)", failsafe_s, 1e3, "ms");
  print_distribution("last setpoint -> levelled (truth)", levelled_s, 1e3, "ms");
  std::printf("  levelled on truth within %.0f ms of the last setpoint: %d of %d vehicles\n",
              1e3 * lim.failsafe_within_s, levelled_in_limit, vehicles);
  print_distribution("touchdown speed", speeds, 1.0, "m/s");
  print_histogram(speeds, 0.05, 2.0 * lim.crash_speed_mps);
  std::printf("  seed %llu, %d cuts per mission, %d worker processes, wall time %.1f s; %s/cuts.csv\n",
              static_cast<unsigned long long>(config.seed), config.cuts_per_mission, config.jobs, wall_s,
              out_dir.c_str());
  return 0;
}

}  // namespace hil::apps
