// `groundstation plan-throw`: the optimal throw of Section III-A (problem (34), solved by
// planning/throw_planner.hpp) and its time-varying LQR gains (planning/throw_tracking.hpp),
// written as CSV files into a directory, with a readable summary.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <string>

#include "groundstation/apps/commands.hpp"
#include "groundstation/model/vehicle_limits.hpp"
#include "groundstation/planning/throw_planner.hpp"
#include "groundstation/planning/throw_reach.hpp"
#include "groundstation/planning/throw_tracking.hpp"
#include "pa/command_line.hpp"

namespace gs::apps {

namespace {

namespace planar = model::planar;

constexpr double kPrintedLaunchThrust_mps2 = 4.48;  // Fig. 5 caption
constexpr const char* kStateNames[planar::kStateSize] = {"x", "z", "vx", "vz", "theta", "alpha", "alpha_dot"};
constexpr const char* kInputNames[planar::kInputSize] = {"aq", "omega_y"};

int failure(const std::string& message) {
  std::fprintf(stderr, "groundstation plan-throw: %s\n", message.c_str());
  return 1;
}

bool write_trajectory(const std::filesystem::path& path, const planning::ThrowTrajectory& traj) {
  std::ofstream csv(path);
  if (!csv) return false;
  csv << "t,x,z,vx,vz,theta,alpha,alpha_dot,a_q,omega_y,F_N\n";
  char line[512];
  for (std::size_t j = 0; j < traj.t_s.size(); ++j) {
    const model::PlanarState<double>& s = traj.state[j];
    const model::PlanarInput<double>& u = traj.input[j];
    std::snprintf(line, sizeof line, "%.9g,%.12g,%.12g,%.12g,%.12g,%.12g,%.12g,%.12g,%.12g,%.12g,%.12g\n",
                  traj.t_s[j], s(planar::kX), s(planar::kZ), s(planar::kVx), s(planar::kVz),
                  s(planar::kTheta), s(planar::kAlpha), s(planar::kAlphaDot), u(planar::kThrust),
                  u(planar::kPitchRate), traj.normal_force_per_mass_mps2[j]);
    csv << line;
  }
  csv.close();
  return static_cast<bool>(csv);
}

bool write_gains(const std::filesystem::path& path, const planning::ThrowTracker& tracker) {
  std::ofstream csv(path);
  if (!csv) return false;
  csv << "t";
  for (const char* input : kInputNames) {
    for (const char* state : kStateNames) csv << ",k_" << input << "_" << state;
  }
  csv << "\n";
  const control::TvLqrGains& gains = tracker.gains();
  char value[32];
  for (std::size_t k = 0; k < gains.times_s().size(); ++k) {
    std::snprintf(value, sizeof value, "%.9g", gains.times_s()[k]);
    csv << value;
    const Eigen::MatrixXd& K = gains.gains()[k];
    for (int r = 0; r < planar::kInputSize; ++r) {
      for (int c = 0; c < planar::kStateSize; ++c) {
        std::snprintf(value, sizeof value, ",%.12g", K(r, c));
        csv << value;
      }
    }
    csv << "\n";
  }
  csv.close();
  return static_cast<bool>(csv);
}

int run(int argc, char** argv) {
  std::string out_dir, limits_path;
  planning::ThrowSolverOptions options;
  CLI::App app("", "groundstation plan-throw");
  pa::cli::describe(
      app, "usage: groundstation plan-throw --out DIR [--intervals N] [--limits FILE]",
      "Solves the paper's throw optimisation (34), Section III-A: from hover at the origin with the\n"
      "pole upright to the Fig. 5 launch state in T = 2.5 s, minimising\n"
      "int 1.5 alpha^2 + (a_q - g)^2 + 8 Omega_y^2 dt with the inputs within the limits and the\n"
      "pole pressed onto the plate (F_N >= 0) throughout; the launch thrust a_q,T is chosen so that\n"
      "F_N = 0 exactly at T. Hermite-Simpson collocation solved by IPOPT, then a time-varying LQR\n"
      "along the result.",
      "Exit 0 when both files were written, 2 on bad arguments, 1 when the solver fails or a file\n"
      "cannot be written.");
  app.add_option("--out", out_dir,
                 "output directory (created if needed):\n"
                 "DIR/throw.csv: t,x,z,vx,vz,theta,alpha,alpha_dot,a_q,omega_y,F_N\n"
                 "  at every collocation point (knots and interval midpoints), SI units,\n"
                 "  F_N per unit pole mass (m/s^2)\n"
                 "DIR/throw_gains.csv: t and the gain K(t) every 5 ms, one column\n"
                 "  k_<input>_<state> per entry, inputs aq, omega_y, states\n"
                 "  x,z,vx,vz,theta,alpha,alpha_dot; u = u_ref(t) - K(t) (s - s_ref(t))")
      ->type_name("DIR")
      ->required()
      ->check(pa::cli::non_empty("wants a directory name"));
  std::uint64_t intervals = static_cast<std::uint64_t>(options.intervals);
  app.add_option("--intervals", intervals, "collocation intervals, 100..2000, default 100")
      ->type_name("N")
      ->check(pa::cli::count(100, 2000, "wants an integer in 100..2000"));
  app.add_option("--limits", limits_path,
                 std::string("input limits file (default: ") + model::kVehicleLimitsRelativePath +
                     " if present,\nelse a_q in [1, 20] m/s^2, |Omega| <= 10 rad/s)")
      ->type_name("FILE")
      ->check(pa::cli::non_empty("wants a file name"));
  if (const std::optional<int> code = pa::cli::parse(app, argc, argv, std::cout, std::cerr)) return *code;
  options.intervals = static_cast<int>(intervals);
  auto usage_error = [&](const std::string& message) {
    std::cerr << "groundstation plan-throw: " << message << "\n\n" << app.help();
    return 2;
  };

  // Limits: the given file, else the repository's file if run from the repository root, else
  // the documented defaults (the same rule as plan-catch).
  planning::ThrowProblem problem;
  std::string limits_source = "built-in defaults";
  std::error_code ec;
  if (limits_path.empty() && std::filesystem::exists(model::kVehicleLimitsRelativePath, ec)) {
    limits_path = model::kVehicleLimitsRelativePath;
  }
  if (!limits_path.empty()) {
    const model::VehicleLimitsLoad load = model::load_vehicle_limits(limits_path);
    if (!load.ok) return usage_error("cannot use the limits: " + load.error);
    problem.limits = load.limits;
    limits_source = limits_path;
  }

  // Wall and process CPU time: on a loaded machine the CPU time is the figure to compare.
  const auto start = std::chrono::steady_clock::now();
  const std::clock_t cpu_start = std::clock();
  const planning::ThrowPlan plan = planning::plan_throw(problem, options);
  const double solve_cpu_ms = 1e3 * static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC;
  const double solve_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  if (!plan.success) {
    std::string message = "the throw optimisation failed: " + plan.status;
    if (plan.iterations > 0) message += " (after " + std::to_string(plan.iterations) + " iterations)";
    return failure(message);
  }
  const planning::ThrowTrackingWeights weights;
  const planning::ThrowTracker tracker(plan.trajectory, weights);
  if (!tracker.valid()) return failure("the TV-LQR design along the throw failed");

  const std::filesystem::path dir(out_dir);
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir)) {
    return failure("cannot create directory " + out_dir + (ec ? ": " + ec.message() : ""));
  }
  const std::filesystem::path traj_path = dir / "throw.csv";
  const std::filesystem::path gains_path = dir / "throw_gains.csv";
  if (!write_trajectory(traj_path, plan.trajectory)) {
    return failure("cannot write " + traj_path.string());
  }
  if (!write_gains(gains_path, tracker)) return failure("cannot write " + gains_path.string());

  const planning::ThrowTrajectory& traj = plan.trajectory;
  double a_min = 1e300, a_max = -1e300, omega_max = 0.0, fn_min_interior = 1e300;
  for (std::size_t j = 0; j < traj.t_s.size(); ++j) {
    a_min = std::min(a_min, traj.input[j](planar::kThrust));
    a_max = std::max(a_max, traj.input[j](planar::kThrust));
    omega_max = std::max(omega_max, std::abs(traj.input[j](planar::kPitchRate)));
    if (j + 1 < traj.t_s.size()) {
      fn_min_interior = std::min(fn_min_interior, traj.normal_force_per_mass_mps2[j]);
    }
  }
  const double a_T = plan.launch_thrust_mps2;
  const model::PlanarState<double>& s_T = problem.launch_state;
  const double fn_printed = model::planar_normal_force_per_mass_mps2<double>(
      s_T(planar::kTheta), s_T(planar::kAlpha), s_T(planar::kAlphaDot), kPrintedLaunchThrust_mps2,
      problem.params);

  std::printf("optimal throw (paper Section III-A, problem (34))\n");
  double h_min = 1e300, h_max = 0.0;
  for (int k = 0; k < traj.intervals(); ++k) {
    h_min = std::min(h_min, traj.t_s[2 * k + 2] - traj.t_s[2 * k]);
    h_max = std::max(h_max, traj.t_s[2 * k + 2] - traj.t_s[2 * k]);
  }
  std::printf("  T = %.3f s, Hermite-Simpson collocation, N = %d intervals of %.2f to %.2f ms"
              " (shortest at the ends), %zu points\n",
              problem.duration_s, traj.intervals(), 1e3 * h_min, 1e3 * h_max, traj.t_s.size());
  std::printf("  solver: IPOPT %s, %d iterations, solve time %.1f ms (%.1f ms CPU)\n", plan.status.c_str(),
              plan.iterations, solve_ms, solve_cpu_ms);
  std::printf("  cost J = %.6f\n", plan.cost);
  std::printf("  end-state error max|s(T) - s_T| = %.3g, max constraint violation %.3g\n",
              plan.end_state_error, plan.max_violation);
  std::printf("  launch state s_T: (x, z) = (%.3f, %.3f) m, (vx, vz) = (%.3f, %.3f) m/s,"
              " theta = %.3f rad, alpha = %.3f rad, alpha_dot = %.3f rad/s\n",
              s_T(planar::kX), s_T(planar::kZ), s_T(planar::kVx), s_T(planar::kVz), s_T(planar::kTheta),
              s_T(planar::kAlpha), s_T(planar::kAlphaDot));
  std::printf("  launch input u_T = (a_q,T, Omega_y,T) = (%.4f m/s^2, %.3f rad/s), F_N(T) = %.2g\n", a_T,
              problem.launch_pitch_rate_radps, traj.normal_force_per_mass_mps2.back());
  std::printf("  a_q,T - printed %.2f = %+.4f m/s^2 (%+.1f %%); the printed value leaves"
              " F_N/m_p = %.4f m/s^2\n",
              kPrintedLaunchThrust_mps2, a_T - kPrintedLaunchThrust_mps2,
              100.0 * (a_T - kPrintedLaunchThrust_mps2) / kPrintedLaunchThrust_mps2, fn_printed);
  std::printf("  inputs: a_q in [%.3f, %.3f] m/s^2, max |Omega_y| %.3f rad/s;"
              " min F_N/m_p before T %.3f m/s^2\n",
              a_min, a_max, omega_max, fn_min_interior);
  const planning::ThrowReach reach = planning::throw_reach(traj, model::PoleParams{});
  std::printf(
      "  reach (the arena's volume must hold it): x %.2f to %.2f m, z %.2f to %.2f m from the "
      "start, the thrower's path and the pole drag-free; the pole's end at most %.2f m above the start\n",
      reach.min_m.x(), reach.max_m.x(), reach.min_m.z(), reach.max_m.z(), reach.pole_apex_m);
  std::printf("  limits (%s): a_q in [%.3f, %.3f] m/s^2, |Omega| <= %.3f rad/s\n", limits_source.c_str(),
              problem.limits.a_q_min_mps2, problem.limits.a_q_max_mps2, problem.limits.omega_max_radps);
  std::printf("  input slew limits (not in (34), so that a vehicle can fly the plan): |a_q'| <= %g "
              "m/s^3, |Omega_y'| <= %g rad/s^2\n",
              problem.thrust_rate_max_mps3, problem.pitch_acceleration_max_radps2);
  const Eigen::VectorXd q = weights.Q().diagonal(), r = weights.R().diagonal();
  std::printf("  TV-LQR: Q = diag(%g, %g, %g, %g, %g, %g, %g), R = diag(%g, %g), Q_f = %g x Q,"
              " %zu gain rows\n",
              q(0), q(1), q(2), q(3), q(4), q(5), q(6), r(0), r(1), weights.terminal_factor,
              tracker.gains().times_s().size());
  std::printf("  wrote %s (%zu rows) and %s\n", traj_path.string().c_str(), traj.t_s.size(),
              gains_path.string().c_str());
  return 0;
}

}  // namespace

int cmd_plan_throw(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "groundstation plan-throw: %s\n", e.what());
    return 1;
  }
}

}  // namespace gs::apps
