#include "groundstation/estimation/mocap_log.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <istream>
#include <ostream>

#include "groundstation/planning/catch_point_predictor.hpp"

namespace gs::estimation {
namespace {

constexpr std::array<std::string_view, 9> kFieldNames = {"t", "body", "x", "y", "z", "qw", "qx", "qy", "qz"};
constexpr double kSameFrame_s = 1e-9;
constexpr double kMaxAbsTime_s = 1e9;  // about 32 years
constexpr double kMaxAbsPosition_m = 1e4;

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

std::string quoted(std::string_view s) {
  constexpr std::size_t kMax = 40;
  std::string out = "'";
  out += s.size() > kMax ? std::string(s.substr(0, kMax)) + "..." : std::string(s);
  out += "'";
  return out;
}

std::optional<double> parse_double(std::string_view s) {
  double value = 0.0;
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (ec != std::errc() || end != s.data() + s.size() || s.empty()) return std::nullopt;
  return value;
}

std::string format(const char* fmt, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, v);
  return buf;
}

}  // namespace

bool is_mocap_header(std::string_view line) {
  line = trim(line);
  std::size_t field = 0;
  while (true) {
    const std::size_t comma = line.find(',');
    const std::string_view name = trim(line.substr(0, comma));
    if (field >= kFieldNames.size() || name != kFieldNames[field]) return false;
    ++field;
    if (comma == std::string_view::npos) break;
    line.remove_prefix(comma + 1);
  }
  return field == kFieldNames.size();
}

MocapRowParse parse_mocap_row(std::string_view line) {
  MocapRowParse result;
  std::array<std::string_view, kFieldNames.size()> fields;
  std::size_t count = 0;
  std::string_view rest = trim(line);
  while (true) {
    const std::size_t comma = rest.find(',');
    if (count < fields.size()) fields[count] = trim(rest.substr(0, comma));
    ++count;
    if (comma == std::string_view::npos) break;
    rest.remove_prefix(comma + 1);
  }
  if (count != fields.size()) {
    result.error = "expected " + std::to_string(fields.size()) + " fields (" + std::string(kMocapLogHeader) +
                   "), got " + std::to_string(count);
    return result;
  }
  std::array<double, kFieldNames.size()> v{};
  for (std::size_t i = 0; i < fields.size(); ++i) {
    if (i == 1) continue;
    const std::optional<double> d = parse_double(fields[i]);
    if (!d) {
      result.error = "field '" + std::string(kFieldNames[i]) + "' is not a number: " + quoted(fields[i]);
      return result;
    }
    if (!std::isfinite(*d)) {
      result.error = "field '" + std::string(kFieldNames[i]) + "' is not finite: " + quoted(fields[i]);
      return result;
    }
    // Beyond these no arena and no clock is real: a corrupt row, not a pose.
    const double limit = i == 0 ? kMaxAbsTime_s : i <= 4 ? kMaxAbsPosition_m : 2.0;
    if (std::abs(*d) > limit) {
      result.error = "field '" + std::string(kFieldNames[i]) + "' is out of range (|" +
                     std::string(kFieldNames[i]) + "| <= " + format("%g", limit) + "): " + quoted(fields[i]);
      return result;
    }
    v[i] = *d;
  }
  MocapRow row;
  const std::string_view body = fields[1];
  if (body == "vehicle1") {
    row.body = MocapBody::vehicle1;
  } else if (body == "vehicle2") {
    row.body = MocapBody::vehicle2;
  } else if (body == "pole") {
    row.body = MocapBody::pole;
  } else {
    result.error = "unknown body " + quoted(body) + " (expected vehicle1, vehicle2 or pole)";
    return result;
  }
  row.t_s = v[0];
  row.pose.p_m = Eigen::Vector3d(v[2], v[3], v[4]);
  row.pose.q = Eigen::Quaterniond(v[5], v[6], v[7], v[8]);
  if (!is_usable_pose(row.pose)) {
    result.error = "quaternion norm " + format("%.4g", row.pose.q.norm()) +
                   " is not close to 1 (expected within [0.5, 1.5])";
    return result;
  }
  row.pose.q.normalize();
  result.row = row;
  return result;
}

ReplaySummary replay_mocap_log(std::istream& in, std::ostream& out, std::ostream& diagnostics,
                               const ReplayOptions& options) {
  ReplaySummary summary;
  std::size_t reported = 0;
  const auto where = [&](std::size_t line_number) {
    return (options.source.empty() ? "line " : options.source + ":") + std::to_string(line_number);
  };
  const auto report = [&](std::size_t line_number, const std::string& what) {
    if (++reported <= options.max_reported_errors) {
      diagnostics << where(line_number) << ": " << what << '\n';
    } else if (reported == options.max_reported_errors + 1) {
      diagnostics << "(further problems are counted but not shown)\n";
    }
  };

  // Read and check every row first: a log is small (200 Hz x 3 bodies), and replaying it in
  // time order keeps one row with a wrong time stamp from discarding the rest.
  struct NumberedRow {
    std::size_t line;
    MocapRow row;
  };
  std::vector<NumberedRow> rows;
  std::string text;
  std::size_t line_number = 0;
  bool header_seen = false;
  while (std::getline(in, text)) {
    ++line_number;
    const std::string_view line = trim(text);
    if (line.empty() || line.front() == '#') continue;
    if (!header_seen) {
      header_seen = true;
      if (is_mocap_header(line)) continue;
      diagnostics << where(line_number) << ": no header row (expected '" << kMocapLogHeader
                  << "'); reading it as data\n";
    } else if (is_mocap_header(line)) {
      ++summary.malformed;
      report(line_number, "repeated header row");
      continue;
    }
    ++summary.rows;
    const MocapRowParse parsed = parse_mocap_row(line);
    if (!parsed.row) {
      ++summary.malformed;
      report(line_number, parsed.error);
      continue;
    }
    if (!rows.empty() && parsed.row->t_s < rows.back().row.t_s - kSameFrame_s) {
      ++summary.reordered;
      report(line_number, "t = " + format("%.6f", parsed.row->t_s) +
                              " is earlier than the row before it (t = " +
                              format("%.6f", rows.back().row.t_s) + "); replayed in time order");
    }
    rows.push_back({line_number, *parsed.row});
  }
  summary.lines = line_number;
  std::stable_sort(rows.begin(), rows.end(), [](const NumberedRow& a, const NumberedRow& b) {
    return a.row.t_s < b.row.t_s - kSameFrame_s;
  });

  StateEstimator estimator(options.config);
  out << kEstimateLogHeader << '\n';
  MocapFrame frame;
  bool frame_open = false;
  std::array<std::size_t, 3> frame_lines{};  // where each body of the open frame came from

  const auto flush = [&]() {
    if (!frame_open) return;
    estimator.update(frame);
    ++summary.frames;
    if (frame.pole) {
      ++summary.pole_frames;
      const PoleEstimate e = estimator.pole();
      const model::PoleState& s = e.state;
      char buf[512];
      std::snprintf(buf, sizeof buf, "%.6f,%s,%.6f,%.6f,%.6f,%.5f,%.5f,%.5f,%.6f,%.6f,%.6f,%.5f,%.5f,%.5f,",
                    frame.t_s, std::string(pole_mode_name(e.mode)).c_str(), s.p_m.x(), s.p_m.y(), s.p_m.z(),
                    s.v_mps.x(), s.v_mps.y(), s.v_mps.z(), s.n.x(), s.n.y(), s.n.z(), s.omega_radps.x(),
                    s.omega_radps.y(), s.omega_radps.z());
      out << buf;
      std::optional<planning::CatchPointPrediction> p;
      if (e.valid && e.mode == PoleMode::free) {
        p = planning::predict_catch_point(s, options.catch_height_m, estimator.pole_model());
      }
      if (p && p->found) {
        ++summary.catch_predictions;
        std::snprintf(buf, sizeof buf, "%.6f,%.6f,%.6f", frame.t_s + p->t_s, p->x_m, p->y_m);
        out << buf;
      } else {
        out << ",,";
      }
      out << '\n';
    }
    frame = MocapFrame{};
    frame_lines = {};
    frame_open = false;
  };

  for (const NumberedRow& r : rows) {
    const MocapRow& row = r.row;
    if (frame_open && row.t_s > frame.t_s + kSameFrame_s) flush();
    if (!frame_open) {
      frame.t_s = row.t_s;
      frame_open = true;
    }
    const std::size_t body = static_cast<std::size_t>(row.body);
    std::optional<MocapPose>& slot =
        row.body == MocapBody::pole ? frame.pole : frame.vehicle[row.body == MocapBody::vehicle2];
    if (slot) {
      ++summary.malformed;
      report(r.line, "a second pose of the same body in the frame at t = " + format("%.6f", row.t_s) +
                         " (first on line " + std::to_string(frame_lines[body]) + "); ignored");
      continue;
    }
    slot = row.pose;
    frame_lines[body] = r.line;
  }
  flush();
  summary.switches = estimator.recent_switches();
  summary.health = estimator.health(estimator.time());
  if (summary.pole_frames == 0) {
    summary.fatal_error = summary.rows == 0 ? "no data rows" : "no usable pole rows";
    return summary;
  }
  summary.ok = true;
  return summary;
}

ReplaySummary replay_mocap_log_file(const std::string& path, std::ostream& out, std::ostream& diagnostics,
                                    ReplayOptions options) {
  std::ifstream in(path);
  if (!in) {
    ReplaySummary summary;
    summary.fatal_error = "cannot read '" + path + "'";
    return summary;
  }
  options.source = path;
  return replay_mocap_log(in, out, diagnostics, options);
}

}  // namespace gs::estimation
