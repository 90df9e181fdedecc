#include "groundstation/planning/catching_instant.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <vector>

#include "groundstation/model/impact.hpp"

namespace gs::planning {
namespace {

// Eq. (42) in the flight's plane (model::flight_plane_yaw_rad) with a fixed choice of contact end
// (tail if !flip, head if flip): continuous in time for that choice.
double residual_with_base(const model::PoleState& state, bool flip, double plane_yaw_rad,
                          const model::PoleParams& params) {
  model::PoleState based = model::turned_by_yaw(state, plane_yaw_rad);
  if (flip) based.n = -based.n;
  return model::catching_condition_residual_radps(model::planar_kinematics(based), params);
}

bool head_is_lower(const model::PoleState& state) { return state.n.z() < 0.0; }

// The state tau after `start`, from a single RK4 step: the same integrator as the step grid.
model::PoleState state_at(const model::PoleState& start, double tau_s, const model::PoleParams& params) {
  if (!(tau_s > 0.0)) return start;
  return model::pole_free_flight_step(start, tau_s, params);
}

// Bisection for the root of residual_with_base(flip) in [lo, hi] (a sign change is known).
double bisect_residual(const model::PoleState& start, double lo, double hi, bool flip, double plane_yaw_rad,
                       const model::PoleParams& params, double tolerance_s) {
  double r_lo = residual_with_base(state_at(start, lo, params), flip, plane_yaw_rad, params);
  while (hi - lo > tolerance_s) {
    const double mid = 0.5 * (lo + hi);
    const double r_mid = residual_with_base(state_at(start, mid, params), flip, plane_yaw_rad, params);
    if ((r_mid > 0.0) == (r_lo > 0.0) && r_mid != 0.0) {
      lo = mid;
      r_lo = r_mid;
    } else {
      hi = mid;
    }
  }
  return 0.5 * (lo + hi);
}

bool sign_change(double a, double b) { return (a > 0.0 && b <= 0.0) || (a < 0.0 && b >= 0.0); }

constexpr std::array<const char*, 11> kThrowCsvColumns = {
    "t", "x", "z", "vx", "vz", "theta", "alpha", "alpha_dot", "a_q", "omega_y", "F_N"};

std::string_view trim_field(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> split_csv_line(std::string_view line) {
  std::vector<std::string_view> fields;
  while (true) {
    const std::size_t comma = line.find(',');
    fields.push_back(trim_field(line.substr(0, comma)));
    if (comma == std::string_view::npos) break;
    line.remove_prefix(comma + 1);
  }
  return fields;
}

LaunchStateLoad csv_failure(std::string_view source, int line, const std::string& what) {
  LaunchStateLoad result;
  result.line = line;
  result.error = std::string(source) + (line > 0 ? ":" + std::to_string(line) : "") + ": " + what;
  return result;
}

}  // namespace

LaunchStateLoad parse_throw_csv_launch_state(std::string_view text, std::string_view source_name) {
  std::array<int, kThrowCsvColumns.size()> column{};
  column.fill(-1);
  std::size_t header_fields = 0;
  bool have_header = false;
  std::vector<double> last_row;
  int last_row_line = 0;
  int line_number = 0;
  while (!text.empty()) {
    const std::size_t eol = text.find('\n');
    const std::string_view line = trim_field(text.substr(0, eol));
    text = eol == std::string_view::npos ? std::string_view{} : text.substr(eol + 1);
    ++line_number;
    if (line.empty()) continue;
    const std::vector<std::string_view> fields = split_csv_line(line);
    if (!have_header) {
      for (std::size_t i = 0; i < fields.size(); ++i) {
        for (std::size_t k = 0; k < kThrowCsvColumns.size(); ++k) {
          if (fields[i] != kThrowCsvColumns[k]) continue;
          if (column[k] >= 0) {
            return csv_failure(source_name, line_number,
                               "duplicate column `" + std::string(fields[i]) + "` in the header");
          }
          column[k] = static_cast<int>(i);
        }
      }
      for (std::size_t k = 0; k < kThrowCsvColumns.size(); ++k) {
        if (column[k] < 0) {
          return csv_failure(source_name, line_number,
                             std::string("header lacks column `") + kThrowCsvColumns[k] +
                                 "` (expected t,x,z,vx,vz,theta,alpha,alpha_dot,a_q,omega_y,F_N)");
        }
      }
      header_fields = fields.size();
      have_header = true;
      continue;
    }
    if (fields.size() != header_fields) {
      return csv_failure(
          source_name, line_number,
          "expected " + std::to_string(header_fields) + " fields, got " + std::to_string(fields.size()));
    }
    std::vector<double> row(fields.size());
    for (std::size_t i = 0; i < fields.size(); ++i) {
      const std::string_view f = fields[i];
      const auto [ptr, ec] = std::from_chars(f.data(), f.data() + f.size(), row[i]);
      if (f.empty() || ec != std::errc{} || ptr != f.data() + f.size() || !std::isfinite(row[i])) {
        return csv_failure(
            source_name, line_number,
            "field " + std::to_string(i + 1) + " is not a finite number: `" + std::string(f) + "`");
      }
    }
    last_row = std::move(row);
    last_row_line = line_number;
  }
  if (!have_header) return csv_failure(source_name, 0, "empty file (no header row)");
  if (last_row.empty()) return csv_failure(source_name, line_number, "no data rows after the header");
  const auto value = [&](const char* name) {
    for (std::size_t k = 0; k < kThrowCsvColumns.size(); ++k) {
      if (std::string_view(kThrowCsvColumns[k]) == name) return last_row[column[k]];
    }
    return 0.0;
  };
  LaunchStateLoad result;
  result.ok = true;
  result.line = last_row_line;
  result.launch = {value("x"), value("z"), value("vx"), value("vz"), value("alpha"), value("alpha_dot")};
  return result;
}

LaunchStateLoad load_throw_csv_launch_state(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return csv_failure(path, 0, "cannot open file");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) return csv_failure(path, 0, "read error");
  return parse_throw_csv_launch_state(buffer.str(), path);
}

PlanarLaunchState launch_state_of(const model::PlanarState<double>& s) {
  namespace planar = model::planar;
  return {s(planar::kX),  s(planar::kZ),     s(planar::kVx),
          s(planar::kVz), s(planar::kAlpha), s(planar::kAlphaDot)};
}

PlanarLaunchState fig5_launch_state() { return {1.5, 2.0, 0.3, 5.5, 0.48, 2.5}; }

// Eq. (23), (26), (27) in the plane; the same as model::free_flight_state_from_pole_on_vehicle() with
// a = L sin alpha, b = 0 (eq. 32), but also valid for |alpha| >= pi/2, which (24) does not cover.
model::PoleState pole_state_at_launch(const PlanarLaunchState& launch, const model::PoleParams& params) {
  const double length = params.half_length_m;
  const double s = std::sin(launch.alpha_rad);
  const double c = std::cos(launch.alpha_rad);
  model::PoleState state;
  state.n = Eigen::Vector3d(s, 0.0, c);
  state.p_m = Eigen::Vector3d(launch.x_m, 0.0, launch.z_m) + length * state.n;
  state.v_mps = Eigen::Vector3d(launch.vx_mps, 0.0, launch.vz_mps) +
                length * launch.alpha_dot_radps * Eigen::Vector3d(c, 0.0, -s);
  state.omega_radps = Eigen::Vector3d(0.0, launch.alpha_dot_radps, 0.0);
  return state;
}

CatchingInstant find_catching_instant(const model::PoleState& launch, const model::PoleParams& params,
                                      const CatchingInstantOptions& options) {
  CatchingInstant result;
  if (!(options.step_s > 0.0) || !(options.horizon_s > 0.0)) return result;
  const double tolerance = options.time_tolerance_s > 0.0 ? options.time_tolerance_s : 1e-10;
  model::PoleState s0 = model::normalised_pole_state(launch);
  const double yaw = options.plane_yaw_rad.value_or(model::flight_plane_yaw_rad(s0));
  double t0 = 0.0;
  while (t0 < options.horizon_s) {
    const double dt = std::min(options.step_s, options.horizon_s - t0);
    const model::PoleState s1 = model::pole_free_flight_step(s0, dt, params);
    const bool flip0 = head_is_lower(s0);
    const bool flip1 = head_is_lower(s1);
    double root = -1.0;
    if (flip0 == flip1) {
      if (sign_change(residual_with_base(s0, flip0, yaw, params),
                      residual_with_base(s1, flip0, yaw, params))) {
        root = bisect_residual(s0, 0.0, dt, flip0, yaw, params, tolerance);
      }
    } else {
      // The pole passes the horizontal inside this step: find that instant and look for a root
      // on each side, each with its own lower end.
      double lo = 0.0;
      double hi = dt;
      while (hi - lo > tolerance) {
        const double mid = 0.5 * (lo + hi);
        (head_is_lower(state_at(s0, mid, params)) == flip0 ? lo : hi) = mid;
      }
      const model::PoleState s_lo = state_at(s0, lo, params);
      const model::PoleState s_hi = state_at(s0, hi, params);
      if (sign_change(residual_with_base(s0, flip0, yaw, params),
                      residual_with_base(s_lo, flip0, yaw, params))) {
        root = bisect_residual(s0, 0.0, lo, flip0, yaw, params, tolerance);
      } else if (sign_change(residual_with_base(s_hi, flip1, yaw, params),
                             residual_with_base(s1, flip1, yaw, params))) {
        root = bisect_residual(s0, hi, dt, flip1, yaw, params, tolerance);
      }
    }
    if (root >= 0.0) {
      result.found = true;
      result.t_s = t0 + root;
      result.pole = state_at(s0, root, params);
      const Eigen::Vector3d lower_end = model::pole_lower_end_m(result.pole, params);
      result.catch_height_m = lower_end.z();
      result.catch_point_m = lower_end.head<2>();
      result.residual_radps =
          model::catching_condition_residual_radps(model::turned_by_yaw(result.pole, yaw), params);
      return result;
    }
    s0 = s1;
    t0 += dt;
  }
  return result;
}

}  // namespace gs::planning
