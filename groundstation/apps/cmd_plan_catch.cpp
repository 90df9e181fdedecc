// `groundstation plan-catch`: the catch manoeuvre of Section V (planning/catch_trajectory.hpp)
// sampled every 1 ms into a CSV, with a summary and the feasibility verdict against eqs. (1), (2).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include "groundstation/apps/commands.hpp"
#include "groundstation/model/vehicle_limits.hpp"
#include "groundstation/planning/catch_trajectory.hpp"
#include "pa/cli/arguments.hpp"

namespace gs::apps {

namespace {

using planning::CatchTrajectory;
using planning::CatchTrajectoryParams;
using planning::InputLimits;

constexpr double kSampleStep_s = 1e-3;  // the firmware's 1 kHz tick; 5 ms would match mocap

void printUsage(std::FILE* out) {
  std::fprintf(
      out,
      "usage: groundstation plan-catch --from X0,Y0 --to XT,YT --catch-height ZT --out FILE\n"
      "                                [--txy T] [--amax A] [--kmax K] [--yaw PSI] [--limits "
      "FILE]\n"
      "\n"
      "Plans the catch manoeuvre of the paper's Section V: a minimum-snap move in x and y from "
      "rest\n"
      "at (X0,Y0) to rest at (XT,YT) over the last T seconds (eq. 45), flown during the "
      "high-thrust\n"
      "phase of a five-phase minimax-acceleration manoeuvre in z that starts hovering at z0 (eq. "
      "49)\n"
      "and ends at rest at the catch height ZT after T_z seconds (eq. 48).\n"
      "\n"
      "  --from X0,Y0        start position (m)\n"
      "  --to XT,YT          catch position (m)\n"
      "  --catch-height ZT   height of the vehicle at the catch (m)\n"
      "  --out FILE          CSV, one row per 1 ms from t = 0 (start of the z manoeuvre) to T_z:\n"
      "                      t,x,y,z,vx,vy,vz,ax,ay,az,a_q,omega_x,omega_y,omega_z (SI units)\n"
      "  --txy T             duration of the xy correction (s), default 0.65\n"
      "  --amax A            z acceleration bound (m/s^2), default 4.19 (Fig. 7); 0 = constant "
      "height\n"
      "  --kmax K            z jerk bound (m/s^3), default 18 (Fig. 7)\n"
      "  --yaw PSI           constant yaw (rad), default 0\n"
      "  --limits FILE       input limits file (default: %s if present,\n"
      "                      else a_q in [1, 20] m/s^2, |Omega| <= 10 rad/s)\n"
      "\n"
      "Prints a summary ending with `feasible: yes` or `feasible: no (<reason>)`; exit 0 when the\n"
      "file was written (feasible or not), 2 on bad arguments, 1 when the file cannot be "
      "written.\n",
      model::kVehicleLimitsRelativePath);
}

int usageError(const std::string& message) {
  std::fprintf(stderr, "groundstation plan-catch: %s\n\n", message.c_str());
  printUsage(stderr);
  return 2;
}

std::optional<Eigen::Vector2d> parsePair(std::string_view text) {
  const std::optional<pa::cli::NumberPair> p = pa::cli::parseNumberPair(text);
  if (!p) return std::nullopt;
  return Eigen::Vector2d(p->first, p->second);
}

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
void forEachSample(const CatchTrajectory& traj, F&& f) {
  const double T = traj.duration_s();
  const auto n = static_cast<long>(std::floor(T / kSampleStep_s + 1e-9));
  for (long k = 0; k <= n; ++k) f(traj.reference(static_cast<double>(k) * kSampleStep_s));
  if (static_cast<double>(n) * kSampleStep_s < T - 1e-12) f(traj.reference(T));
}

std::string describe(planning::Feasibility kind, const planning::LimitViolation& v) {
  char buf[200];
  switch (kind) {
    case planning::Feasibility::kThrustTooHigh:
      std::snprintf(buf, sizeof buf, "thrust_too_high: a_q = %.3f m/s^2 > %.3f at t = %.3f s",
                    v.value, v.limit, v.t_s);
      break;
    case planning::Feasibility::kThrustTooLow:
      std::snprintf(buf, sizeof buf, "thrust_too_low: a_q = %.3f m/s^2 < %.3f at t = %.3f s",
                    v.value, v.limit, v.t_s);
      break;
    case planning::Feasibility::kRatesTooHigh:
      std::snprintf(buf, sizeof buf, "rates_too_high: |Omega_%c| = %.3f rad/s > %.3f at t = %.3f s",
                    "xyz"[v.axis < 0 ? 1 : v.axis], v.value, v.limit, v.t_s);
      break;
    default:
      return "";
  }
  return buf;
}

// The verdict's reason first, then any other violated limit.
std::string describeViolations(const planning::FeasibilityVerdict& verdict) {
  std::string text = describe(verdict.reason, verdict.primary());
  const std::pair<planning::Feasibility, const planning::LimitViolation*> all[] = {
      {planning::Feasibility::kThrustTooHigh, &verdict.thrust_high},
      {planning::Feasibility::kThrustTooLow, &verdict.thrust_low},
      {planning::Feasibility::kRatesTooHigh, &verdict.rates}};
  for (const auto& [kind, v] : all) {
    if (kind != verdict.reason && v->violated) text += "; also " + describe(kind, *v);
  }
  return text;
}

int run(int argc, char** argv) {
  std::optional<Eigen::Vector2d> from, to;
  std::optional<double> catch_height;
  std::string out_path, limits_path;
  CatchTrajectoryParams params;
  for (int i = 1; i < argc; ++i) {
    const std::string_view flag = argv[i];
    if (flag == "--help" || flag == "-h") {
      printUsage(stdout);
      return 0;
    }
    if (i + 1 >= argc) return usageError("missing value after " + std::string(flag));
    const std::string_view value = argv[++i];
    auto number = [&](double& target) {
      const auto v = pa::cli::parseNumber(value);
      if (v) target = *v;
      return v.has_value();
    };
    if (flag == "--from") {
      if (!(from = parsePair(value))) return usageError("--from wants X0,Y0 in metres");
    } else if (flag == "--to") {
      if (!(to = parsePair(value))) return usageError("--to wants XT,YT in metres");
    } else if (flag == "--catch-height") {
      double z = 0;
      if (!number(z)) return usageError("--catch-height wants a number (m)");
      catch_height = z;
    } else if (flag == "--txy") {
      if (!number(params.t_xy_s)) return usageError("--txy wants a number (s)");
    } else if (flag == "--amax") {
      if (!number(params.a_max_mps2)) return usageError("--amax wants a number (m/s^2)");
    } else if (flag == "--kmax") {
      if (!number(params.k_max_mps3)) return usageError("--kmax wants a number (m/s^3)");
    } else if (flag == "--yaw") {
      if (!number(params.yaw_rad)) return usageError("--yaw wants a number (rad)");
    } else if (flag == "--out") {
      out_path = value;
      if (out_path.empty()) return usageError("--out wants a file name");
    } else if (flag == "--limits") {
      limits_path = value;
    } else {
      return usageError("unknown argument " + std::string(flag));
    }
  }
  if (!from) return usageError("--from is required");
  if (!to) return usageError("--to is required");
  if (!catch_height) return usageError("--catch-height is required");
  if (out_path.empty()) return usageError("--out is required");
  params.start_xy_m = *from;
  params.target_xy_m = *to;
  params.catch_height_m = *catch_height;
  if (const auto error = planning::validate(params); error != planning::CatchParamError::kNone) {
    return usageError(std::string(planning::toString(error)));
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
    const model::VehicleLimitsLoad load = model::loadVehicleLimits(limits_path);
    if (!load.ok) return usageError("cannot use the limits: " + load.error);
    limits = {load.limits.a_q_min_mps2, load.limits.a_q_max_mps2, load.limits.omega_max_radps};
    limits_source = limits_path;
  }

  const std::optional<CatchTrajectory> traj = CatchTrajectory::create(params);
  if (!traj) return usageError("invalid manoeuvre parameters");
  const planning::FeasibilityVerdict verdict = traj->checkFeasibility(limits);

  std::ofstream csv(out_path);
  if (!csv) {
    std::fprintf(stderr, "groundstation plan-catch: cannot open %s for writing\n",
                 out_path.c_str());
    return 1;
  }
  csv << "t,x,y,z,vx,vy,vz,ax,ay,az,a_q,omega_x,omega_y,omega_z\n";
  Peaks peaks;
  long rows = 0;
  char line[512];
  forEachSample(*traj, [&](const planning::CatchReference& r) {
    std::snprintf(line, sizeof line,
                  "%.6f,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", r.t_s,
                  r.position_m.x(), r.position_m.y(), r.position_m.z(), r.velocity_mps.x(),
                  r.velocity_mps.y(), r.velocity_mps.z(), r.acceleration_mps2.x(),
                  r.acceleration_mps2.y(), r.acceleration_mps2.z(), r.thrust_mps2,
                  // + 0.0 turns -0 into 0 in the file.
                  r.body_rates_radps.x() + 0.0, r.body_rates_radps.y() + 0.0,
                  r.body_rates_radps.z() + 0.0);
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
    forEachSample(*flat_traj, [&](const planning::CatchReference& r) { flat_peaks.add(r); });
  }

  const auto& t = traj->zManoeuvre().phaseTimes_s();
  std::printf("catch manoeuvre (paper Section V)\n");
  std::printf("  xy: (%.3f, %.3f) m -> (%.3f, %.3f) m, minimum snap over T_xy = %.3f s (eq. 45)\n",
              params.start_xy_m.x(), params.start_xy_m.y(), params.target_xy_m.x(),
              params.target_xy_m.y(), params.t_xy_s);
  std::printf("  z:  %.3f m -> %.3f m, a_max = %.3f m/s^2, k_max = %.3f m/s^3, yaw %.3f rad\n",
              traj->startHeight_m(), params.catch_height_m, params.a_max_mps2, params.k_max_mps3,
              params.yaw_rad);
  std::printf("  T_z = %.4f s (eq. 48), z0 = %.4f m (eq. 49), drop %.4f m\n", traj->duration_s(),
              traj->startHeight_m(), traj->startHeight_m() - params.catch_height_m);
  std::printf(
      "  phases t0..t5 = %.4f %.4f %.4f %.4f %.4f %.4f s (jerk -k, 0, +k, 0, -k);"
      " xy over [t3, t5]\n",
      t[0], t[1], t[2], t[3], t[4], t[5]);
  std::printf("  a_q: max %.3f m/s^2 at t = %.3f s, min %.3f m/s^2 at t = %.3f s\n",
              peaks.thrust_max, peaks.thrust_max_t, peaks.thrust_min, peaks.thrust_min_t);
  std::printf("  |Omega|: x %.3f, y %.3f, z %.3f rad/s (peaks at t = %.3f, %.3f, %.3f s)\n",
              peaks.rate_max.x(), peaks.rate_max.y(), peaks.rate_max.z(), peaks.rate_max_t.x(),
              peaks.rate_max_t.y(), peaks.rate_max_t.z());
  std::printf(
      "  at constant height the same xy correction needs a_q max %.3f m/s^2,"
      " |Omega| max (%.3f, %.3f, %.3f) rad/s\n",
      flat_peaks.thrust_max, flat_peaks.rate_max.x(), flat_peaks.rate_max.y(),
      flat_peaks.rate_max.z());
  std::printf("  limits (%s): a_q in [%.3f, %.3f] m/s^2, |Omega_i| <= %.3f rad/s\n",
              limits_source.c_str(), limits.a_q_min_mps2, limits.a_q_max_mps2,
              limits.omega_max_radps);
  if (verdict.feasible() && !verdict.certified) {
    std::printf(
        "  note: within the limits at every checked instant, but a limit is approached"
        " within the bound's slack over 1 ms\n");
  }
  std::printf("  wrote %ld rows (every %.0f ms, t = 0 .. T_z) to %s\n", rows, kSampleStep_s * 1e3,
              out_path.c_str());
  if (verdict.feasible()) {
    std::printf("feasible: yes\n");
  } else {
    std::printf("feasible: no (%s)\n", describeViolations(verdict).c_str());
  }
  return 0;
}

}  // namespace

int cmdPlanCatch(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "groundstation plan-catch: %s\n", e.what());
    return 1;
  }
}

}  // namespace gs::apps
