// `groundstation estimate`: replays a recorded motion-capture log through the estimator
// (Section IV) offline and writes the pole estimate with its catch-point prediction as CSV
// (estimation/mocap_log.hpp).
#include <cmath>
#include <cstdio>
#include <exception>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>

#include "groundstation/apps/commands.hpp"
#include "groundstation/estimation/mocap_log.hpp"
#include "pa/command_line.hpp"

namespace gs::apps {

namespace {

int run(int argc, char** argv) {
  std::string mocap_path;
  std::string out_path;
  double catch_height = 0.0;
  double drag_scale = 1.0;
  bool fixed_drag = false;
  CLI::App app("", "groundstation estimate");
  pa::cli::describe(
      app,
      "usage: groundstation estimate --mocap FILE.csv --catch-height Z --out FILE.csv\n"
      "                              [--drag-scale K] [--fixed-drag]",
      "Replays a recorded motion-capture log through the estimator of the paper's Section IV\n"
      "(vehicle observers and the hybrid pole estimator: free flight, on vehicle 1, on vehicle 2),\n"
      "offline, without the commanded inputs.",
      "Malformed rows are reported on stderr with their line number and skipped. Exit 0 when the\n"
      "estimate was written, 1 when the input cannot be read or holds no usable pole row, 2 on\n"
      "bad arguments.");
  app.add_option("--mocap", mocap_path,
                 "input CSV with the header " + std::string(estimation::kMocapLogHeader) +
                     "\n(SI units; body is vehicle1, vehicle2 or pole; q turns the body frame into the\n"
                     "inertial one, for the pole its z-axis into the pole direction)")
      ->type_name("FILE")
      ->required();
  app.add_option("--catch-height", catch_height, "catching height (m) for the lower end's predicted crossing")
      ->type_name("Z")
      ->required()
      ->check(pa::cli::finite_number("must be a number (m)"));
  app.add_option("--out", out_path,
                 "output CSV ('-' for stdout), one row per pole frame:\n" +
                     std::string(estimation::kEstimateLogHeader) +
                     "\n(catch_* empty when no crossing is predicted)")
      ->type_name("FILE")
      ->required();
  app.add_option("--drag-scale", drag_scale, "the model's drag coefficients times K (default 1: the paper's)")
      ->type_name("K")
      ->check(pa::cli::number_in(0.0, 10.0, "must be in [0, 10]"));
  app.add_flag("--fixed-drag", fixed_drag, "do not estimate the drag online");
  if (const std::optional<int> code = pa::cli::parse(app, argc, argv, std::cout, std::cerr)) return *code;

  estimation::ReplayOptions options;
  options.catch_height_m = catch_height;
  for (model::PoleParams* p : {&options.config.free_flight.pole, &options.config.on_vehicle.pole}) {
    p->drag_axial *= drag_scale;
    p->drag_normal *= drag_scale;
    p->drag_rotational *= drag_scale;
  }
  options.config.free_flight.estimate_drag_scale = !fixed_drag;

  // The estimate goes to memory first, so that a failed run leaves no half-written file.
  std::ostringstream estimate;
  std::ostringstream diagnostics;
  const estimation::ReplaySummary summary =
      estimation::replay_mocap_log_file(mocap_path, estimate, diagnostics, options);
  std::fputs(diagnostics.str().c_str(), stderr);
  if (!summary.ok && summary.lines == 0 && summary.fatal_error.rfind("cannot read", 0) == 0) {
    std::fprintf(stderr, "groundstation estimate: %s\n", summary.fatal_error.c_str());
    return 1;
  }
  if (!summary.ok) {
    std::fprintf(stderr, "groundstation estimate: %s in '%s': nothing to estimate\n",
                 summary.fatal_error.c_str(), mocap_path.c_str());
    return 1;
  }
  if (out_path == "-") {
    std::fputs(estimate.str().c_str(), stdout);
  } else {
    std::ofstream out(out_path);
    out << estimate.str();
    out.flush();
    if (!out) {
      std::fprintf(stderr, "groundstation estimate: cannot write '%s'\n", out_path.c_str());
      return 1;
    }
  }

  std::fprintf(stderr,
               "estimate: %zu data rows (%zu malformed, skipped; %zu out of time order, sorted), "
               "%zu frames, %zu with the pole, %zu with a catch prediction\n",
               summary.rows, summary.malformed, summary.reordered, summary.frames, summary.pole_frames,
               summary.catch_predictions);
  const estimation::EstimatorHealth& h = summary.health;
  std::fprintf(stderr,
               "estimate: motion capture %.1f Hz (vehicle1 %.1f, vehicle2 %.1f); pole NIS mean "
               "%.2f (5 dof, recent), %llu of %llu above the 99%% gate, %llu poses rejected; drag "
               "scale %.3f\n",
               h.pole.rate_Hz, h.vehicle[0].rate_Hz, h.vehicle[1].rate_Hz, h.pole.mean_nis,
               static_cast<unsigned long long>(h.pole.nis_exceedances),
               static_cast<unsigned long long>(h.pole.samples),
               static_cast<unsigned long long>(h.pole.rejected), h.drag_scale);
  for (const estimation::ModeSwitch& s : summary.switches) {
    std::fprintf(stderr, "estimate: t = %.4f s: %s -> %s (%s, event at %.4f s)\n", s.detected_t_s,
                 std::string(estimation::pole_mode_name(s.from)).c_str(),
                 std::string(estimation::pole_mode_name(s.to)).c_str(),
                 std::string(estimation::switch_reason_name(s.reason)).c_str(), s.event_t_s);
  }
  if (out_path != "-") std::fprintf(stderr, "estimate: wrote %s\n", out_path.c_str());
  return 0;
}

}  // namespace

int cmd_estimate(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "groundstation estimate: internal error: %s\n", e.what());
  } catch (...) {
    std::fprintf(stderr, "groundstation estimate: internal error\n");
  }
  return 1;
}

}  // namespace gs::apps
