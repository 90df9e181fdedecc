// `groundstation plan-catch`: the catch manoeuvre of Section V (planning/catch_trajectory.hpp)
// sampled every 1 ms into a CSV, with a summary and the feasibility verdict against eqs. (1), (2).
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <string>
#include <utility>

#include "groundstation/apps/commands.hpp"
#include "groundstation/model/vehicle_limits.hpp"
#include "groundstation/planning/catch_trajectory.hpp"
#include "pa/command_line.hpp"

namespace gs::apps {

namespace {

using planning::CatchTrajectory;
using planning::CatchTrajectoryParams;
using planning::InputLimits;

constexpr double kSampleStep_s = 1e-3;  // the firmware's 1 kHz tick; 5 ms would match mocap

struct Peaks {
  double thrust_max = -1.0, thrust_max_t = 0.0;
  double thrust_min = 1e300, thrust_min_t = 0.0;
  Eigen::Vector3d rate_max = Eigen::Vector3d::Zero();
  Eigen::Vector3d rate_max_t = Eigen::Vector3d::Zero();
  void add(const planning::CatchReference& r) {
    if (r.thrust_mps2 > thrust_max) thrust_max = r.thrust_mps2, thrust_max_t = r.t_s;
    if (r.thrust_mps2 < thrust_min) thrust_min = r.thrust_mps2, thrust_min_t = r.t_s;
    for (int i = 0; i < 3; ++i) {
      if (std::abs(r.body_rates_radps(i)) > rate_max(i)) {
        rate_max(i) = std::abs(r.body_rates_radps(i));
        rate_max_t(i) = r.t_s;
      }
    }
  }
};

// Sample times 0, 1 ms, ..., and T_z itself.
template <typename F>
void for_each_sample(const CatchTrajectory& traj, F&& f) {
  const double T = traj.duration_s();
  const auto n = static_cast<long>(std::floor(T / kSampleStep_s + 1e-9));
  for (long k = 0; k <= n; ++k) f(traj.reference(static_cast<double>(k) * kSampleStep_s));
  if (static_cast<double>(n) * kSampleStep_s < T - 1e-12) f(traj.reference(T));
}

std::string describe(planning::Feasibility kind, const planning::LimitViolation& v) {
  char buf[200];
  switch (kind) {
    case planning::Feasibility::thrust_too_high:
      std::snprintf(buf, sizeof buf, "thrust_too_high: a_q = %.3f m/s^2 > %.3f at t = %.3f s", v.value,
                    v.limit, v.t_s);
      break;
    case planning::Feasibility::thrust_too_low:
      std::snprintf(buf, sizeof buf, "thrust_too_low: a_q = %.3f m/s^2 < %.3f at t = %.3f s", v.value,
                    v.limit, v.t_s);
      break;
    case planning::Feasibility::rates_too_high:
      std::snprintf(buf, sizeof buf, "rates_too_high: |Omega_%c| = %.3f rad/s > %.3f at t = %.3f s",
                    "xyz"[v.axis < 0 ? 1 : v.axis], v.value, v.limit, v.t_s);
      break;
    default: return "";
  }
  return buf;
}

// The verdict's reason first, then any other violated limit.
std::string describe_violations(const planning::FeasibilityVerdict& verdict) {
  std::string text = describe(verdict.reason, verdict.primary());
  const std::pair<planning::Feasibility, const planning::LimitViolation*> all[] = {
      {planning::Feasibility::thrust_too_high, &verdict.thrust_high},
      {planning::Feasibility::thrust_too_low, &verdict.thrust_low},
      {planning::Feasibility::rates_too_high, &verdict.rates}};
  for (const auto& [kind, v] : all) {
    if (kind != verdict.reason && v->violated) text += "; also " + describe(kind, *v);
  }
  return text;
}

int run(int argc, char** argv) {
  std::string from, to, out_path, limits_path;
  double catch_height = 0.0;
  CatchTrajectoryParams params;
  CLI::App app("", "groundstation plan-catch");
  pa::cli::describe(
      app,
      "usage: groundstation plan-catch --from X0,Y0 --to XT,YT --catch-height ZT --out FILE\n"
      "                                [--txy T] [--amax A] [--kmax K] [--yaw PSI] [--limits FILE]",
      "Plans the catch manoeuvre of the paper's Section V: a minimum-snap move in x and y from rest\n"
      "at (X0,Y0) to rest at (XT,YT) over the last T seconds (eq. 45), flown during the high-thrust\n"
      "phase of a five-phase minimax-acceleration manoeuvre in z that starts hovering at z0 (eq. 49)\n"
      "and ends at rest at the catch height ZT after T_z seconds (eq. 48).",
      "Prints a summary ending with `feasible: yes` or `feasible: no (<reason>)`; exit 0 when the\n"
      "file was written (feasible or not), 2 on bad arguments, 1 when the file cannot be written.");
  app.add_option("--from", from, "start position (m)")
      ->type_name("X0,Y0")
      ->required()
      ->check(pa::cli::number_pair("wants X0,Y0 in metres"));
  app.add_option("--to", to, "catch position (m)")
      ->type_name("XT,YT")
      ->required()
      ->check(pa::cli::number_pair("wants XT,YT in metres"));
  app.add_option("--catch-height", catch_height, "height of the vehicle at the catch (m)")
      ->type_name("ZT")
      ->required()
      ->check(pa::cli::finite_number("wants a number (m)"));
  app.add_option("--out", out_path,
                 "CSV, one row per 1 ms from t = 0 (start of the z manoeuvre) to T_z:\n"
                 "t,x,y,z,vx,vy,vz,ax,ay,az,a_q,omega_x,omega_y,omega_z (SI units)")
      ->type_name("FILE")
      ->required()
      ->check(pa::cli::non_empty("wants a file name"));
  app.add_option("--txy", params.t_xy_s, "duration of the xy correction (s), default 0.65")
      ->type_name("T")
      ->check(pa::cli::finite_number("wants a number (s)"));
  app.add_option("--amax", params.a_max_mps2,
                 "z acceleration bound (m/s^2), default 4.19 (Fig. 7); 0 = constant height")
      ->type_name("A")
      ->check(pa::cli::finite_number("wants a number (m/s^2)"));
  app.add_option("--kmax", params.k_max_mps3, "z jerk bound (m/s^3), default 18 (Fig. 7)")
      ->type_name("K")
      ->check(pa::cli::finite_number("wants a number (m/s^3)"));
  app.add_option("--yaw", params.yaw_rad, "constant yaw (rad), default 0")
      ->type_name("PSI")
      ->check(pa::cli::finite_number("wants a number (rad)"));
  app.add_option("--limits", limits_path,
                 std::string("input limits file (default: ") + model::kVehicleLimitsRelativePath +
                     " if present,\nelse a_q in [1, 20] m/s^2, |Omega| <= 10 rad/s)")
      ->type_name("FILE");
  if (const std::optional<int> code = pa::cli::parse(app, argc, argv, std::cout, std::cerr)) return *code;
  auto usage_error = [&](const std::string& message) {
    std::cerr << "groundstation plan-catch: " << message << "\n\n" << app.help();
    return 2;
  };
  const pa::cli::NumberPair start = pa::cli::to_number_pair(from);
  const pa::cli::NumberPair target = pa::cli::to_number_pair(to);
  params.start_xy_m = Eigen::Vector2d(start.first, start.second);
  params.target_xy_m = Eigen::Vector2d(target.first, target.second);
  params.catch_height_m = catch_height;
  if (const auto error = planning::validate(params); error != planning::CatchParamError::none) {
    return usage_error(std::string(planning::to_string(error)));
  }

  // Limits: the given file, else the repository's file if run from the repository root, else
  // the documented defaults (docs/paper-notes.md: roughly 1-20 m/s^2 and 10 rad/s for the platform).
  InputLimits limits;
  std::string limits_source = "built-in defaults";
  std::error_code ec;
  if (limits_path.empty() && std::filesystem::exists(model::kVehicleLimitsRelativePath, ec)) {
    limits_path = model::kVehicleLimitsRelativePath;
  }
  if (!limits_path.empty()) {
    const model::VehicleLimitsLoad load = model::load_vehicle_limits(limits_path);
    if (!load.ok) return usage_error("cannot use the limits: " + load.error);
    limits = {load.limits.a_q_min_mps2, load.limits.a_q_max_mps2, load.limits.omega_max_radps};
    limits_source = limits_path;
  }

  const std::optional<CatchTrajectory> traj = CatchTrajectory::create(params);
  if (!traj) return usage_error("invalid manoeuvre parameters");
  const planning::FeasibilityVerdict verdict = traj->check_feasibility(limits);

  std::ofstream csv(out_path);
  if (!csv) {
    std::fprintf(stderr, "groundstation plan-catch: cannot open %s for writing\n", out_path.c_str());
    return 1;
  }
  csv << "t,x,y,z,vx,vy,vz,ax,ay,az,a_q,omega_x,omega_y,omega_z\n";
  Peaks peaks;
  long rows = 0;
  char line[512];
  for_each_sample(*traj, [&](const planning::CatchReference& r) {
    std::snprintf(line, sizeof line,
                  "%.6f,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", r.t_s,
                  r.position_m.x(), r.position_m.y(), r.position_m.z(), r.velocity_mps.x(),
                  r.velocity_mps.y(), r.velocity_mps.z(), r.acceleration_mps2.x(), r.acceleration_mps2.y(),
                  r.acceleration_mps2.z(), r.thrust_mps2,
                  // + 0.0 turns -0 into 0 in the file.
                  r.body_rates_radps.x() + 0.0, r.body_rates_radps.y() + 0.0, r.body_rates_radps.z() + 0.0);
    csv << line;
    peaks.add(r);
    ++rows;
  });
  csv.close();
  if (!csv) {
    std::fprintf(stderr, "groundstation plan-catch: writing %s failed\n", out_path.c_str());
    return 1;
  }

  // The same correction at constant height (Fig. 7, dashed) for comparison.
  CatchTrajectoryParams flat = params;
  flat.a_max_mps2 = 0.0;
  Peaks flat_peaks;
  if (const auto flat_traj = CatchTrajectory::create(flat)) {
    for_each_sample(*flat_traj, [&](const planning::CatchReference& r) { flat_peaks.add(r); });
  }

  const auto& t = traj->z_manoeuvre().phase_times_s();
  std::printf("catch manoeuvre (paper Section V)\n");
  std::printf("  xy: (%.3f, %.3f) m -> (%.3f, %.3f) m, minimum snap over T_xy = %.3f s (eq. 45)\n",
              params.start_xy_m.x(), params.start_xy_m.y(), params.target_xy_m.x(), params.target_xy_m.y(),
              params.t_xy_s);
  std::printf("  z:  %.3f m -> %.3f m, a_max = %.3f m/s^2, k_max = %.3f m/s^3, yaw %.3f rad\n",
              traj->start_height_m(), params.catch_height_m, params.a_max_mps2, params.k_max_mps3,
              params.yaw_rad);
  std::printf("  T_z = %.4f s (eq. 48), z0 = %.4f m (eq. 49), drop %.4f m\n", traj->duration_s(),
              traj->start_height_m(), traj->start_height_m() - params.catch_height_m);
  std::printf("  phases t0..t5 = %.4f %.4f %.4f %.4f %.4f %.4f s (jerk -k, 0, +k, 0, -k);"
              " xy over [t3, t5]\n",
              t[0], t[1], t[2], t[3], t[4], t[5]);
  std::printf("  a_q: max %.3f m/s^2 at t = %.3f s, min %.3f m/s^2 at t = %.3f s\n", peaks.thrust_max,
              peaks.thrust_max_t, peaks.thrust_min, peaks.thrust_min_t);
  std::printf("  |Omega|: x %.3f, y %.3f, z %.3f rad/s (peaks at t = %.3f, %.3f, %.3f s)\n",
              peaks.rate_max.x(), peaks.rate_max.y(), peaks.rate_max.z(), peaks.rate_max_t.x(),
              peaks.rate_max_t.y(), peaks.rate_max_t.z());
  std::printf("  at constant height the same xy correction needs a_q max %.3f m/s^2,"
              " |Omega| max (%.3f, %.3f, %.3f) rad/s\n",
              flat_peaks.thrust_max, flat_peaks.rate_max.x(), flat_peaks.rate_max.y(),
              flat_peaks.rate_max.z());
  std::printf("  limits (%s): a_q in [%.3f, %.3f] m/s^2, |Omega_i| <= %.3f rad/s\n", limits_source.c_str(),
              limits.a_q_min_mps2, limits.a_q_max_mps2, limits.omega_max_radps);
  if (verdict.feasible() && !verdict.certified) {
    std::printf("  note: within the limits at every checked instant, but a limit is approached"
                " within the bound's slack over 1 ms\n");
  }
  std::printf("  wrote %ld rows (every %.0f ms, t = 0 .. T_z) to %s\n", rows, kSampleStep_s * 1e3,
              out_path.c_str());
  if (verdict.feasible()) {
    std::printf("feasible: yes\n");
  } else {
    std::printf("feasible: no (%s)\n", describe_violations(verdict).c_str());
  }
  return 0;
}

}  // namespace

int cmd_plan_catch(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "groundstation plan-catch: %s\n", e.what());
    return 1;
  }
}

}  // namespace gs::apps
