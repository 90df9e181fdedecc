// `groundstation catch-instant`: the optimal catching instant of Section III-B
// (planning/catching_instant.hpp) from the Fig. 5 launch state or the end of a planned throw,
// with the nominal catching height and catch point, compared with the paper's measured figures.
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>

#include "groundstation/apps/commands.hpp"
#include "groundstation/model/impact.hpp"
#include "groundstation/planning/catching_instant.hpp"
#include "pa/command_line.hpp"

namespace gs::apps {

namespace {

// Section VII-B: means over the paper's 9 throws, measured in flight (docs/paper-notes.md).
constexpr double kPaperFreeFlight_s = 0.812;
constexpr double kPaperCatchHeight_m = 1.343;

int run(int argc, char** argv) {
  std::string launch_path;
  bool no_drag = false;
  CLI::App app("", "groundstation catch-instant");
  pa::cli::describe(
      app, "usage: groundstation catch-instant [--launch-from FILE|DIR] [--no-drag]",
      "Finds the optimal catching instant of the paper's Section III-B: the pole flies freely\n"
      "(eq. 20, with drag) from the launch until the first instant at which a vehicle at rest\n"
      "catching its lower end would leave it exactly the energy to swing up to the upright (41),\n"
      "i.e. eq. (42) in the sign convention of groundstation/model/impact.hpp. Prints that instant,\n"
      "the nominal catching height (lower pole end) and the catch point.",
      "Exit 0 when an instant was found, 1 when none lies within 3 s of flight, 2 on bad\n"
      "arguments or a malformed launch file.");
  app.add_option("--launch-from", launch_path,
                 "launch from the end of a planned throw: the last row of the CSV P (or\n"
                 "P/throw.csv if P is a directory), as written by `groundstation\n"
                 "plan-throw --out DIR`, header t,x,z,vx,vz,theta,alpha,alpha_dot,a_q,\n"
                 "omega_y,F_N. Default: the Fig. 5 end state (x, z) = (1.5, 2.0) m,\n"
                 "(vx, vz) = (0.3, 5.5) m/s, alpha = 0.48 rad, alpha' = 2.5 rad/s.")
      ->type_name("P")
      ->check(pa::cli::non_empty("needs a file or directory"));
  app.add_flag("--no-drag", no_drag, "fly without aerodynamic drag (c_z = c_xy = c_rot = 0), for comparison");
  if (const std::optional<int> code = pa::cli::parse(app, argc, argv, std::cout, std::cerr)) return *code;
  const bool drag = !no_drag;

  gs::planning::PlanarLaunchState launch = gs::planning::fig5_launch_state();
  std::string launch_source = "Fig. 5 end state";
  if (!launch_path.empty()) {
    std::error_code ec;
    if (std::filesystem::is_directory(launch_path, ec)) {
      launch_path = (std::filesystem::path(launch_path) / "throw.csv").string();
    }
    const gs::planning::LaunchStateLoad load = gs::planning::load_throw_csv_launch_state(launch_path);
    if (!load.ok) {
      std::fprintf(stderr, "groundstation catch-instant: %s\n", load.error.c_str());
      return 2;
    }
    launch = load.launch;
    launch_source = launch_path + ", last row (line " + std::to_string(load.line) + ")";
  }

  gs::model::PoleParams params;
  if (!drag) params = gs::model::without_drag(params);
  const gs::model::PoleState pole = gs::planning::pole_state_at_launch(launch, params);
  const gs::planning::CatchingInstantOptions options;
  const gs::planning::CatchingInstant ci = gs::planning::find_catching_instant(pole, params, options);

  std::printf("launch state:             %s\n", launch_source.c_str());
  std::printf("                          x %.4f m, z %.4f m, vx %.4f m/s, vz %.4f m/s,\n"
              "                          alpha %.4f rad, alpha_dot %.4f rad/s\n",
              launch.x_m, launch.z_m, launch.vx_mps, launch.vz_mps, launch.alpha_rad, launch.alpha_dot_radps);
  if (drag) {
    std::printf("drag:                     on (c_z %.1f, c_xy %.1f, c_rot %.1f g/m^2)\n",
                1e3 * params.drag_axial, 1e3 * params.drag_normal, 1e3 * params.drag_rotational);
  } else {
    std::printf("drag:                     off\n");
  }
  if (!ci.found) {
    std::printf("catching instant:         none within %.1f s of flight\n", options.horizon_s);
    return 1;
  }
  const gs::model::PlanarPoleKinematics k = gs::model::planar_kinematics_from_lower_end(ci.pole);
  const gs::model::ImpactResult impact = gs::model::impact_map(ci.pole, Eigen::Vector3d::Zero(), params);
  const double rate_after = impact.after.omega_radps.y();
  std::printf("catching instant:         %.4f s after launch\n", ci.t_s);
  std::printf("nominal catching height:  %.4f m (lower pole end)\n", ci.catch_height_m);
  std::printf("catch point (x, y):       %.4f, %.4f m (lower pole end)\n", ci.catch_point_m.x(),
              ci.catch_point_m.y());
  std::printf("pole before the catch:    alpha %.4f rad (lower end to centre), alpha_dot %.4f "
              "rad/s,\n"
              "                          centre velocity (%.4f, %.4f) m/s; residual of (42) %.1e "
              "rad/s\n",
              k.alpha_rad, k.alpha_dot_radps, k.x_dot_mps, k.z_dot_mps, ci.residual_radps);
  std::printf("after a catch at rest:    alpha_dot %.4f rad/s, energy %.5f J (E* = m_p g L = "
              "%.5f J)\n",
              rate_after, gs::model::pivoted_pole_energy_J(k.alpha_rad, rate_after, params),
              gs::model::upright_energy_J(params));
  std::printf("paper (measured, mean of 9 throws): free flight %.3f s, catching height %.3f m\n",
              kPaperFreeFlight_s, kPaperCatchHeight_m);
  std::printf("this minus paper:         %+.3f s, %+.3f m\n", ci.t_s - kPaperFreeFlight_s,
              ci.catch_height_m - kPaperCatchHeight_m);
  return 0;
}

}  // namespace

int cmd_catch_instant(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "groundstation catch-instant: %s\n", e.what());
    return 1;
  }
}

}  // namespace gs::apps
