// `hil fly (--series paper | --throws N | --passes N | --targets N) [--seed S] [--plant FILE] [--randomise] [--out DIR]`:
// a series of throws flown in the lockstep arena by the ground-station runtime (hil/trials/series.hpp),
// judged on the plant's truth. Prints a table per throw and a summary beside the paper's figures;
// with --out writes DIR/throws.csv (one row per attempt), DIR/attempt_<n>.csv (its time series)
// and DIR/report.html (hil/apps/report.hpp; not with --no-report). Columns: docs/report.md.
// `--firmware qemu --pil-image ELF`: processor in the loop, each vehicle flown by the flight image
// in its own QEMU (hil/sil/emulated_firmware.hpp) instead of the core in process; prints what the
// ticks cost in guest instructions and the wall time per simulated second.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "hil/apps/commands.hpp"
#include "hil/apps/flight_output.hpp"
#include "hil/apps/report.hpp"
#include "hil/plant/plant_config.hpp"
#include "hil/trials/series.hpp"
#include "hil/trials/trial_config.hpp"
#include "pa/command_line.hpp"

namespace hil::apps {
namespace {

using gs::adaptation::ThrowOutcome;

constexpr const char* kUsage =
    "usage: hil fly (--series paper | --throws N | --passes N | --targets N) [--seed S] [--plant FILE] [--randomise] [--out DIR [--no-report]] [--store FILE] [--land] [--verbose]\n"
    "               [--firmware host | --firmware qemu --pil-image ELF [--qemu PATH] [--icount-shift N] [--pil-timeout S]]";

int usage(const std::string& message) {
  std::cerr << "hil fly: " << message << "\n" << kUsage << "\n";
  return 2;
}

// How close the throws to targets came: the ground station's converged prediction and the true
// impact, each against its target.
void print_target_summary(const std::vector<trials::AttemptResult>& results) {
  std::vector<double> predicted, impact;
  for (const trials::AttemptResult& r : results) {
    if (r.predicted_target_miss_m >= 0.0) predicted.push_back(r.predicted_target_miss_m);
    if (r.target_miss_m >= 0.0) impact.push_back(r.target_miss_m);
  }
  auto describe = [](std::vector<double> v) {
    if (v.empty()) return std::string("none");
    std::sort(v.begin(), v.end());
    char text[120];
    std::snprintf(text, sizeof text, "median %.1f mm, max %.1f mm (%zu throws)", 1e3 * v[v.size() / 2],
                  1e3 * v.back(), v.size());
    return std::string(text);
  };
  std::printf("         targets: catch point predicted 0.1 s after the launch vs the target: %s; true "
              "impact vs the target: %s\n",
              describe(predicted).c_str(), describe(impact).c_str());
}

// Processor in the loop: what each image's ticks cost in guest instructions (every step's
// HIL_TICK_COST, through the series' on_step), by phase of the act, against the self-test's
// budget (firmware/ports/mps2_an386: 1,500 instructions per 1 kHz tick), and the wall time.
// A vehicle's phase is its ground-station task, except the impact: the catcher's first
// kImpactWindow_s after the pole touched its plate while it was catching (the firmware's impact
// detection, classification and catch reaction start in it).
class TickCosts {
 public:
  static constexpr std::uint32_t kBudget = 1500;
  static constexpr double kImpactWindow_s = 0.1;
  enum Phase : std::size_t { ground, hover, balance, throwing, catching, impact, landing, failsafe, kPhases };
  static constexpr std::array<const char*, kPhases> kNames = {"ground (parked, arming)",
                                                              "hover (take-off, hover, wait, retreat, clear)",
                                                              "balance",
                                                              "throw (throw, release)",
                                                              "catch (before the impact)",
                                                              "impact (first 0.1 s)",
                                                              "landing",
                                                              "failsafe"};

  void watch(trials::SeriesConfig& config) {
    config.on_step = [this](const sil::Arena& arena, const gs::runtime::GroundStation& gs) {
      for (const pa::VehicleId v : pa::kActVehicles) {
        const std::optional<std::uint32_t> n = arena.vehicle(v).last_tick_instructions();
        if (!n) continue;
        const std::size_t i = pa::act_slot(v);
        const gs::mission::Task task = gs.task(v);
        const bool touched =
            arena.plant().pole_contact() == (v == pa::kVehicle1 ? Contact::vehicle1 : Contact::vehicle2);
        if (task == gs::mission::Task::catching && touched && !impact_start_s_[i])
          impact_start_s_[i] = arena.t_s();
        // Caught, the catcher rebalances and balances within milliseconds: the window runs on.
        if (task != gs::mission::Task::catching && task != gs::mission::Task::rebalance &&
            task != gs::mission::Task::balance)
          impact_start_s_[i].reset();
        const bool in_impact = impact_start_s_[i] && arena.t_s() - *impact_start_s_[i] < kImpactWindow_s;
        phases_[i][in_impact ? impact : phase(task)].add(*n);
        all_[i].add(*n);
      }
    };
  }
  void print(double simulated_s, double wall_s) const {
    for (const pa::VehicleId v : pa::kActVehicles) {
      const std::size_t i = pa::act_slot(v);
      const Stats& a = all_[i];
      std::printf(
          "     pil vehicle %d: %llu ticks, guest instructions per tick mean %.0f, max %u (budget %u)\n",
          int(v.node()), static_cast<unsigned long long>(a.n), a.mean(), a.max, kBudget);
      for (std::size_t p = 0; p < kPhases; ++p) {
        const Stats& s = phases_[i][p];
        if (s.n == 0) continue;
        std::printf("         %-46s %6llu ticks  mean %5.0f  max %5u%s\n", kNames[p],
                    static_cast<unsigned long long>(s.n), s.mean(), s.max,
                    s.max > kBudget ? "  over budget" : "");
      }
    }
    std::printf("     pil: %.3f simulated s in %.1f s of wall time, %.2f s per simulated s\n", simulated_s,
                wall_s, simulated_s > 0.0 ? wall_s / simulated_s : 0.0);
  }

 private:
  static Phase phase(gs::mission::Task task) {
    using gs::mission::Task;
    switch (task) {
      case Task::parked:
      case Task::arming: return ground;
      case Task::balance:
      case Task::rebalance: return balance;
      case Task::throwing:
      case Task::release: return throwing;
      case Task::catching: return catching;
      case Task::landing:
      case Task::descend: return landing;
      case Task::failsafe: return failsafe;
      case Task::take_off:
      case Task::hover:
      case Task::retreat:
      case Task::wait:
      case Task::clear: break;
    }
    return hover;
  }
  struct Stats {
    std::uint64_t n = 0;
    double sum = 0.0;
    std::uint32_t max = 0;
    void add(std::uint32_t x) {
      ++n;
      sum += x;
      max = std::max(max, x);
    }
    double mean() const { return n > 0 ? sum / static_cast<double>(n) : 0.0; }
  };
  std::array<Stats, 2> all_{};
  std::array<std::array<Stats, kPhases>, 2> phases_{};
  std::array<std::optional<double>, 2> impact_start_s_{};
};

}  // namespace

int cmd_fly(int argc, char** argv) {
  std::string series, plant_file, out_dir, store_file;
  std::uint64_t throws = 0, passes = 0, targets = 0, seed = 1;
  bool randomise = false, verbose = false, no_report = false, no_trial = false, land = false;
  std::string firmware = "host", pil_image, qemu = "qemu-system-arm";
  std::optional<std::uint64_t> icount_shift;
  double pil_timeout_s = 10.0;
  CLI::App app("", "hil fly");
  pa::cli::describe(
      app, kUsage,
      "Flies a series of throws in the lockstep arena with the ground-station runtime, judged\n"
      "on the plant's truth; prints a table per throw and a summary beside the paper's figures.");
  app.add_option("--series", series, "the paper's series of throws")
      ->type_name("paper")
      ->check(pa::cli::one_of({"paper"}, "must be 'paper'"));
  app.add_option("--throws", throws, "N throws to catch instead")
      ->type_name("N")
      ->check(pa::cli::count(1, 100000, "needs a count 1..100000"));
  app.add_flag("--no-trial", no_trial,
               "with --throws: catch from the first throw, without the trial throw that only adapts (what "
               "`groundstation op throw` flies)");
  app.add_option("--passes", passes,
                 "N passes back and forth: vehicle 1 throws to vehicle 2, which catches and throws back")
      ->type_name("N")
      ->check(pa::cli::count(1, 100000, "needs a count 1..100000"));
  app.add_option(
         "--targets", targets,
         "N throws to targets 2.5-4.5 m away all round, each planned for the point where vehicle 2 waits")
      ->type_name("N")
      ->check(pa::cli::count(1, 1000, "needs a count 1..1000"));
  app.add_option("--seed", seed, "seed of the noise and of --randomise (default 1)")
      ->type_name("S")
      ->check(pa::cli::count(0, UINT64_MAX, "needs a non-negative integer"));
  app.add_option("--plant", plant_file, "plant configuration (default: the built-in one)")->type_name("FILE");
  app.add_flag(
      "--randomise", randomise,
      "each attempt on a plant drawn anew from the seed (--passes, --targets: all on one plant drawn from it)");
  app.add_option("--out", out_dir, "write DIR/throws.csv, DIR/attempt_<n>.csv and DIR/report.html")
      ->type_name("DIR");
  app.add_flag("--no-report", no_report, "with --out: the CSV files only, no report.html");
  app.add_option("--store", store_file, "the ground station's adaptation store")->type_name("FILE");
  app.add_flag("--land", land, "after the last attempt the pole is taken down and both vehicles land");
  app.add_flag("--verbose", verbose, "print the mission log");
  app.add_option("--firmware", firmware,
                 "what flies the vehicles: the firmware core in process (host, the default) or the flight "
                 "image in QEMU, one per vehicle (qemu: processor in the loop)")
      ->type_name("host|qemu")
      ->check(pa::cli::one_of({"host", "qemu"}, "must be 'host' or 'qemu'"));
  app.add_option("--pil-image", pil_image, "with --firmware qemu: the PIL image (fw_mps2_an386_pil.elf)")
      ->type_name("ELF");
  app.add_option("--qemu", qemu, "with --firmware qemu: the emulator (default qemu-system-arm)")
      ->type_name("PATH");
  std::string shift_help = "with --firmware qemu: QEMU's -icount shift, the image's PA_MPS2_ICOUNT_SHIFT";
  if (sil::kImageIcountShift) shift_help += " (default " + std::to_string(*sil::kImageIcountShift) + ")";
  app.add_option("--icount-shift", icount_shift, shift_help)
      ->type_name("N")
      ->check(pa::cli::count(0, 10, "needs a count 0..10"));
  app.add_option("--pil-timeout", pil_timeout_s,
                 "with --firmware qemu: seconds of wall time to wait for each tick's answer (default 10)")
      ->type_name("S")
      ->check(pa::cli::number_in(0.01, 3600.0, "needs seconds 0.01..3600"));
  if (const std::optional<int> code = pa::cli::parse(app, argc, argv, std::cout, std::cerr)) return *code;
  if (int(!series.empty()) + int(throws > 0) + int(passes > 0) + int(targets > 0) != 1)
    return usage("give exactly one of --series paper, --throws N, --passes N and --targets N");
  if (no_trial && throws == 0) return usage("--no-trial goes with --throws N");
  std::optional<sil::EmulatorConfig> emulator;
  if (firmware == "qemu") {
    if (pil_image.empty()) return usage("--firmware qemu needs --pil-image ELF");
    std::error_code ec;
    if (!std::filesystem::is_regular_file(pil_image, ec))
      return usage("--pil-image '" + pil_image + "' is not a file (build it with the cortex-m4 preset)");
    emulator.emplace();
    emulator->image = pil_image;
    emulator->qemu = qemu;
    if (icount_shift) emulator->icount_shift = static_cast<int>(*icount_shift);
    if (!emulator->icount_shift)
      return usage("--firmware qemu needs --icount-shift N (this build could not read the image's)");
    emulator->answer_timeout_s = pil_timeout_s;
  } else if (!pil_image.empty() || icount_shift || app.count("--qemu") > 0 ||
             app.count("--pil-timeout") > 0) {
    return usage("--pil-image, --qemu, --icount-shift and --pil-timeout go with --firmware qemu");
  }

  PlantConfig plant;
  if (!plant_file.empty()) {
    std::string error;
    if (!load_plant_config(plant_file, plant, error)) {
      std::cerr << "hil fly: " << error << "\n";
      return 2;
    }
  }
  const gs::runtime::GroundStationConfig ground_station;
  const std::vector<trials::AttemptPlan> plans =
      series == "paper" ? trials::paper_series()
      : passes > 0      ? trials::pass_series(static_cast<int>(passes))
      : targets > 0
          ? trials::target_series(static_cast<int>(targets), ground_station.throw_origin_m.head<2>())
          : trials::catch_series(static_cast<int>(throws), !no_trial);
  if (!out_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(out_dir, ec);
    if (ec) {
      std::cerr << "hil fly: cannot create '" << out_dir << "': " << ec.message() << "\n";
      return 1;
    }
  }

  std::vector<trials::AttemptResult> results;
  TickCosts tick_costs;
  double simulated_s = 0.0;
  bool landed = true;
  const auto wall_start = std::chrono::steady_clock::now();
  try {
    std::printf(
        "throw  outcome          flight_s  height_m  catch_x_m  catch_y_m  travel_m  energy_err_J  abort\n");
    auto print = [&](const trials::AttemptResult& r) {
      std::printf("%5d  %-15s  %8.3f  %8.3f  %9.3f  %9.3f  %8.3f  %12.5f  %s%s\n", r.throw_number,
                  std::string(gs::adaptation::to_string(r.outcome)).c_str(), r.flight_s, r.catch_height_m,
                  r.catch_x_m, r.catch_y_m, r.travel_m, r.energy_error_J, r.abort_reason.c_str(),
                  r.vehicle_crashed ? " (vehicle crashed)" : "");
      if (r.predicted_target_miss_m >= 0.0)
        std::printf("       target: predicted %.1f mm, impact %.1f mm from it\n",
                    1e3 * r.predicted_target_miss_m, 1e3 * r.target_miss_m);
      std::fflush(stdout);
    };
    if (!randomise || passes > 0 || targets > 0) {
      // Passes and targets fly one series on one plant: randomised, drawn once from the seed.
      trials::SeriesConfig config = trials::trial_config(
          plant, seed, randomise ? trials::PlantDraw::drawn : trials::PlantDraw::as_given);
      config.record_time_series = !out_dir.empty();
      config.ground_station.adaptation_store_path = store_file;
      // Before a throw or a pass, a spent pack is swapped (SeriesConfig::swap_spent_packs).
      config.swap_spent_packs = throws > 0 || passes > 0;
      config.land_after = land;
      config.arena.emulated_firmware = emulator;
      if (emulator) tick_costs.watch(config);
      if (verbose) config.log = [](const std::string& line) { std::printf("%s\n", line.c_str()); };
      trials::SeriesRunner runner(config);
      results = runner.run(plans, print);
      simulated_s += runner.simulated_time_s();
      landed = runner.landed();
      print_identification(runner.ground_station(), runner.arena().plant());
      if (runner.packs_swapped() > 0)
        std::printf("         packs swapped between throws (spent for the throw): %d\n",
                    runner.packs_swapped());
      if (!out_dir.empty()) {
        for (std::size_t i = 0; i < runner.time_series().size(); ++i)
          write_time_series(out_dir + "/attempt_" + std::to_string(i + 1) + ".csv", runner.time_series()[i]);
      }
    } else {
      // Each attempt on a plant drawn anew from its ranges: one series of one throw per draw,
      // after the throw that adapts only. Attempt k is seeded attempt_seed(seed, k), as attempt k
      // of a campaign (trial_config.hpp). What the ground station learnt carries over from draw
      // to draw, as its store would.
      std::optional<gs::adaptation::Learnt> learnt;
      for (std::size_t i = 0; i < plans.size(); ++i) {
        trials::SeriesConfig config = trials::trial_config(
            plant, trials::attempt_seed(seed, static_cast<int>(i) + 1), trials::PlantDraw::drawn);
        config.ground_station.learnt = learnt;
        config.ground_station.adaptation_store_path = store_file;
        config.record_time_series = !out_dir.empty();
        config.land_after = land && i + 1 == plans.size();
        config.arena.emulated_firmware = emulator;
        if (emulator) tick_costs.watch(config);
        if (verbose) config.log = [](const std::string& line) { std::printf("%s\n", line.c_str()); };
        trials::SeriesRunner runner(config);
        std::vector<trials::AttemptPlan> one{plans[i]};
        trials::AttemptResult r = runner.run(one).front();
        simulated_s += runner.simulated_time_s();
        if (config.land_after) landed = runner.landed();
        learnt = runner.ground_station().learnt();
        if (!out_dir.empty() && !runner.time_series().empty())
          write_time_series(out_dir + "/attempt_" + std::to_string(i + 1) + ".csv",
                            runner.time_series().front());
        if (verbose)
          std::printf(
              "  learnt: catching height %.3f, waiting (%.3f, %.3f), bias (%.3f, %.3f), catching instant %.3f s\n",
              learnt->state.catch_height_m, learnt->state.waiting_xy_m.x(), learnt->state.waiting_xy_m.y(),
              learnt->state.offset_bias_m.x(), learnt->state.offset_bias_m.y(), learnt->catch_instant_s);
        r.throw_number = static_cast<int>(i) + 1;
        print(r);
        results.push_back(r);
      }
    }

  } catch (const gs::adaptation::StoreError& e) {
    std::cerr << "hil fly: " << e.what() << "\n";
    return 2;
  } catch (const sil::EmulatedFirmwareError& e) {
    std::fflush(stdout);
    std::cerr << "hil fly: " << e.what() << "\n";
    return 1;
  }
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  // The summary in plain words, beside the paper's figures (Section VII-B, Fig. 10).
  std::map<std::string, int> counts;
  int caught = 0, catches = 0, impacts = 0;
  double energy_sum = 0.0, flight_sum = 0.0;
  for (const trials::AttemptResult& r : results) {
    ++counts[std::string(gs::adaptation::to_string(r.outcome))];
    if (r.outcome == ThrowOutcome::caught) ++caught;
    if (r.outcome != ThrowOutcome::throw_only && r.outcome != ThrowOutcome::offset_practice) ++catches;
    if (r.impact && (r.outcome == ThrowOutcome::caught || r.outcome == ThrowOutcome::dropped)) {
      energy_sum += std::abs(r.energy_error_J);
      flight_sum += r.flight_s;
      ++impacts;
    }
  }
  std::printf("summary: %d of %d attempts to catch were caught and balanced again for 3 s (", caught,
              catches);
  bool first = true;
  for (const auto& [outcome, n] : counts) {
    std::printf("%s%s %d", first ? "" : ", ", outcome.c_str(), n);
    first = false;
  }
  std::printf(")\n");
  if (impacts > 0) {
    std::printf("         pole energy right after the impact within %.4f J of E* on average (the paper: "
                "0.0102 J); free flight to the impact %.3f s on average (the paper: 0.812 s)\n",
                energy_sum / impacts, flight_sum / impacts);
  }
  if (passes > 0) {
    // After the throw that adapts only.
    const auto first_miss =
        std::find_if(results.begin() + 1, results.end(),
                     [](const trials::AttemptResult& r) { return r.outcome != ThrowOutcome::caught; });
    std::printf("         passes: %d consecutive passes caught without a drop (of %llu, after the throw that "
                "adapts; vehicle 1 throws the odd passes, vehicle 2 the even ones)\n",
                static_cast<int>(first_miss - results.begin() - 1), static_cast<unsigned long long>(passes));
  }
  if (targets > 0) print_target_summary(results);
  std::printf("         no vehicle crashed: %s\n",
              std::none_of(results.begin(), results.end(),
                           [](const trials::AttemptResult& r) { return r.vehicle_crashed; })
                  ? "yes"
                  : "NO");
  if (land) std::printf("         both vehicles landed after the last attempt: %s\n", landed ? "yes" : "NO");
  if (emulator) tick_costs.print(simulated_s, wall_s);
  if (!out_dir.empty()) {
    std::ofstream csv(out_dir + "/throws.csv");
    trials::write_csv(csv, trials::fly_throws_columns(), results);
    csv.close();
    if (!no_report) make_report(out_dir, "hil fly");
  }
  return 0;
}

}  // namespace hil::apps
