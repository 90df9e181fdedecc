#include "groundstation/adaptation/history_report.hpp"

#include <charconv>
#include <cstdarg>
#include <cstdio>
#include <optional>

namespace gs::adaptation {
namespace {

std::string format(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
std::string format(const char* fmt, ...) {
  char buffer[256];
  va_list args;
  va_start(args, fmt);
  std::vsnprintf(buffer, sizeof buffer, fmt, args);
  va_end(args);
  return buffer;
}

std::string pad(const std::string& text, std::size_t width) {
  return text.size() >= width ? text + " " : text + std::string(width - text.size() + 1, ' ');
}

std::string point_cell(const Eigen::Vector2d& xy, double t_s) {
  return format("(%+.3f,%+.3f)@%.3f", xy.x(), xy.y(), t_s);
}

// The note on one line.
std::string one_line(std::string text) {
  for (char& c : text) {
    if (c == '\n' || c == '\r' || c == '\t') c = ' ';
  }
  return text;
}

struct Column {
  const char* title;
  std::size_t width;
};

constexpr Column kColumns[] = {
    {"id", 5},
    {"time_s", 15},
    {"outcome", 20},
    {"launch x,y,z m", 20},
    {"launch vx,vy,vz m/s", 20},
    {"alpha", 6},
    {"alpha'", 6},
    {"h_used", 6},
    {"predicted x,y m @t s", 23},
    {"actual x,y m @t s", 23},
    {"optimal h m (x,y m) @t s", 31},
    {"bias x,y m", 15},
    {"|E-E*| J", 8},
    {"note", 0},
};

// The shortest text that reads back as the same double: the CSV loses nothing of the store.
std::string csv_real(const std::optional<double>& value) {
  if (!value) return {};
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, *value);
  return std::string(buffer, result.ptr);
}

std::string csv_text(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

std::string sample_summary(std::int64_t n, const char* what) {
  return n == 0 ? std::string("no ") + what + " yet" : std::to_string(n) + " " + what;
}

// One line of cells padded to their columns, without trailing blanks.
template <std::size_t N>
void write_line(std::ostream& out, const Column (&columns)[N], const std::string (&cells)[N]) {
  std::string line;
  for (std::size_t i = 0; i < N; ++i) line += pad(cells[i], columns[i].width);
  while (!line.empty() && line.back() == ' ') line.pop_back();
  out << line << "\n";
}

template <std::size_t N>
void write_header(std::ostream& out, const Column (&columns)[N]) {
  std::string titles[N];
  for (std::size_t i = 0; i < N; ++i) titles[i] = columns[i].title;
  write_line(out, columns, titles);
}

constexpr Column kIdentificationColumns[] = {
    {"id", 5},      {"vehicle", 7},        {"time_s", 15},   {"outcome", 14}, {"lag ms", 6}, {"95 % ms", 11},
    {"inertia", 7}, {"round trip ms", 13}, {"rms rad/s", 9}, {"samples", 7},  {"k", 0},
};

std::string optional_cell(const std::optional<double>& value, const char* fmt) {
  return value ? format(fmt, *value) : "-";
}

std::string at_time(const StoredIdentification& i) {
  return format("identification %lld at t %.3f s", static_cast<long long>(i.id), i.record.time_s);
}

}  // namespace

void write_history_table(std::ostream& out, const std::vector<StoredThrow>& throws) {
  write_header(out, kColumns);
  for (const StoredThrow& t : throws) {
    const ThrowRecord& r = t.record;
    std::string cells[std::size(kColumns)];
    cells[0] = std::to_string(t.id);
    cells[1] = format("%.3f", r.time_s);
    cells[2] = std::string(to_string(r.outcome));
    cells[3] = format("%+.2f,%+.2f,%+.2f", r.launch.x_m, r.launch_y_m, r.launch.z_m);
    cells[4] = format("%+.2f,%+.2f,%+.2f", r.launch.vx_mps, r.launch_vy_mps, r.launch.vz_mps);
    cells[5] = format("%+.3f", r.launch.alpha_rad);
    cells[6] = format("%+.2f", r.launch.alpha_dot_radps);
    cells[7] = format("%.3f", r.catch_height_used_m);
    cells[8] = r.predicted ? point_cell(r.predicted->xy_m, r.predicted->t_s) : "-";
    cells[9] = r.actual ? point_cell(r.actual->xy_m, r.actual->t_s) : "-";
    cells[10] =
        r.optimal ? format("%.3f ", r.optimal->height_m) + point_cell(r.optimal->xy_m, r.optimal->t_s) : "-";
    const std::optional<Eigen::Vector2d> bias = offset_bias_sample(r);
    cells[11] = bias ? format("%+.3f,%+.3f", bias->x(), bias->y()) : "-";
    cells[12] = t.energy_error_J ? format("%.4f", *t.energy_error_J) : "-";
    cells[13] = one_line(r.note);
    write_line(out, kColumns, cells);
  }
}

void write_identification_table(std::ostream& out, const std::vector<StoredIdentification>& identifications) {
  write_header(out, kIdentificationColumns);
  for (const StoredIdentification& i : identifications) {
    const IdentificationRecord& r = i.record;
    const std::optional<estimation::MotorIdentification>& m = r.result.identified;
    std::string cells[std::size(kIdentificationColumns)];
    cells[0] = std::to_string(i.id);
    cells[1] = std::to_string(r.vehicle.node());
    cells[2] = format("%.3f", r.time_s);
    cells[3] = std::string(outcome_name(r.result));
    cells[4] = m ? format("%.1f", 1e3 * m->time_constant_s) : "-";
    cells[5] = m ? format("%.1f-%.1f", 1e3 * m->time_constant_low_s, 1e3 * m->time_constant_high_s) : "-";
    cells[6] = m ? format("%.3f", m->inertia_gain) : "-";
    cells[7] = m ? format("%.1f", 1e3 * m->round_trip_s) : "-";
    cells[8] = m ? format("%.4f", m->rms_radps) : "-";
    cells[9] = m ? std::to_string(m->samples) : "-";
    cells[10] = optional_cell(r.thrust_gain, "%.4f");
    write_line(out, kIdentificationColumns, cells);
  }
}

std::string identification_csv_header() {
  return "id,vehicle,time_s,outcome,time_constant_s,time_constant_low_s,time_constant_high_s,"
         "inertia_gain,round_trip_s,rms_radps,samples,thrust_gain";
}

void write_identification_csv(std::ostream& out, const std::vector<StoredIdentification>& identifications) {
  out << identification_csv_header() << "\n";
  for (const StoredIdentification& i : identifications) {
    const IdentificationRecord& r = i.record;
    const std::optional<estimation::MotorIdentification>& m = r.result.identified;
    const auto fit = [&](double estimation::MotorIdentification::*field) {
      return csv_real(m ? std::optional<double>((*m).*field) : std::nullopt);
    };
    out << i.id << "," << static_cast<int>(r.vehicle.node()) << "," << csv_real(r.time_s) << ","
        << outcome_name(r.result) << "," << fit(&estimation::MotorIdentification::time_constant_s) << ","
        << fit(&estimation::MotorIdentification::time_constant_low_s) << ","
        << fit(&estimation::MotorIdentification::time_constant_high_s) << ","
        << fit(&estimation::MotorIdentification::inertia_gain) << ","
        << fit(&estimation::MotorIdentification::round_trip_s) << ","
        << fit(&estimation::MotorIdentification::rms_radps) << "," << (m ? std::to_string(m->samples) : "")
        << "," << csv_real(r.thrust_gain) << "\n";
  }
}

void write_identification_summary(std::ostream& out, const std::vector<VehicleIdentifications>& vehicles) {
  if (vehicles.empty()) {
    out << "  motor identifications: none\n";
    return;
  }
  out << "  motor identifications (per vehicle the last accepted, set on board at arming when it "
         "differs from the design lag):\n";
  for (const VehicleIdentifications& v : vehicles) {
    out << "    vehicle " << static_cast<int>(v.vehicle.node()) << ": ";
    if (const std::optional<StoredIdentification>& a = v.last_accepted) {
      const estimation::MotorIdentification& m = *a->record.result.identified;
      out << format("lag %.1f ms (95 %%: %.1f-%.1f ms), inertia %.3f, round trip %.1f ms, thrust gain %s; ",
                    1e3 * m.time_constant_s, 1e3 * m.time_constant_low_s, 1e3 * m.time_constant_high_s,
                    m.inertia_gain, 1e3 * m.round_trip_s,
                    optional_cell(a->record.thrust_gain, "%.4f").c_str())
          << at_time(*a);
    } else {
      out << "no accepted identification (the firmware's design lag stays)";
    }
    out << " (" << v.count << (v.count == 1 ? " identification" : " identifications") << ")\n";
    if (!v.latest.accepted()) {
      out << "      latest refused: " << outcome_name(v.latest.record.result) << ", " << at_time(v.latest)
          << (v.last_accepted ? "; the lag above is kept" : "") << "\n";
    }
  }
}

std::string history_csv_header() {
  return "id,time_s,outcome,thrower,launch_x_m,launch_y_m,launch_z_m,launch_vx_mps,launch_vy_mps,"
         "launch_vz_mps,launch_alpha_rad,launch_alpha_dot_radps,catch_height_used_m,waiting_x_m,"
         "waiting_y_m,target_x_m,target_y_m,predicted_x_m,predicted_y_m,predicted_t_s,"
         "actual_x_m,actual_y_m,actual_t_s,optimal_t_s,optimal_height_m,optimal_x_m,optimal_y_m,"
         "catcher_x_m,catcher_y_m,bias_sample_x_m,bias_sample_y_m,energy_J,energy_error_J,note";
}

void write_history_csv(std::ostream& out, const std::vector<StoredThrow>& throws) {
  out << history_csv_header() << "\n";
  for (const StoredThrow& t : throws) {
    const ThrowRecord& r = t.record;
    auto x = [](const std::optional<Eigen::Vector2d>& v) { return v ? std::optional(v->x()) : std::nullopt; };
    auto y = [](const std::optional<Eigen::Vector2d>& v) { return v ? std::optional(v->y()) : std::nullopt; };
    const auto predicted_xy = r.predicted ? std::optional(r.predicted->xy_m) : std::nullopt;
    const auto actual_xy = r.actual ? std::optional(r.actual->xy_m) : std::nullopt;
    const auto optimal_xy = r.optimal ? std::optional(r.optimal->xy_m) : std::nullopt;
    const std::optional<Eigen::Vector2d> bias = offset_bias_sample(r);
    const std::optional<double> fields[] = {
        r.time_s,
        r.launch.x_m,
        r.launch_y_m,
        r.launch.z_m,
        r.launch.vx_mps,
        r.launch_vy_mps,
        r.launch.vz_mps,
        r.launch.alpha_rad,
        r.launch.alpha_dot_radps,
        r.catch_height_used_m,
        r.waiting_xy_m.x(),
        r.waiting_xy_m.y(),
        x(r.target_xy_m),
        y(r.target_xy_m),
        x(predicted_xy),
        y(predicted_xy),
        r.predicted ? std::optional(r.predicted->t_s) : std::nullopt,
        x(actual_xy),
        y(actual_xy),
        r.actual ? std::optional(r.actual->t_s) : std::nullopt,
        r.optimal ? std::optional(r.optimal->t_s) : std::nullopt,
        r.optimal ? std::optional(r.optimal->height_m) : std::nullopt,
        x(optimal_xy),
        y(optimal_xy),
        x(r.catcher_at_impact_xy_m),
        y(r.catcher_at_impact_xy_m),
        x(bias),
        y(bias),
        r.energy_after_impact_J,
        t.energy_error_J,
    };
    out << t.id;
    out << "," << csv_real(fields[0]) << "," << to_string(r.outcome) << ","
        << (r.thrower ? std::to_string(r.thrower->node()) : std::string());
    for (std::size_t i = 1; i < std::size(fields); ++i) out << "," << csv_real(fields[i]);
    out << "," << csv_text(r.note) << "\n";
  }
}

void write_adaptation_summary(std::ostream& out, const std::string& path, const AdaptationSettings& settings,
                              const AdaptationSnapshot& snapshot, const ConsistencyReport& consistency) {
  const AdaptationState& a = snapshot.state;
  out << "adaptation store " << path << " (schema " << kSchemaVersion << ")\n";
  if (snapshot.throw_count == 0) {
    out << "  throws recorded:     none\n";
  } else {
    out << "  throws recorded:     " << snapshot.throw_count << " (ids 1.." << snapshot.last_throw_id << ")";
    if (snapshot.epoch_first_id > snapshot.last_throw_id) {
      out << "; reset after throw " << snapshot.last_throw_id << ", no throw since";
    } else if (snapshot.epoch_first_id > 1) {
      out << "; reset before throw " << snapshot.epoch_first_id << ", the values rest on throws "
          << snapshot.epoch_first_id << ".." << snapshot.last_throw_id;
    }
    out << "\n";
  }
  out << format("  catching height:     %.4f m   (%s; nominal %.4f m)\n", a.catch_height_m,
                sample_summary(a.catch_point_samples, "throws").c_str(), settings.nominal_catch_height_m);
  out << format("  waiting position:    (%.4f, %.4f) m   (%s; nominal (%.4f, %.4f) m)\n", a.waiting_xy_m.x(),
                a.waiting_xy_m.y(), sample_summary(a.catch_point_samples, "throws").c_str(),
                settings.nominal_waiting_xy_m.x(), settings.nominal_waiting_xy_m.y());
  out << format("  catcher offset bias: (%+.4f, %+.4f) m   (%s; the catch trajectory is shifted "
                "by minus this)\n",
                a.offset_bias_m.x(), a.offset_bias_m.y(), sample_summary(a.bias_samples, "catches").c_str());
  if (settings.window == 0) {
    out << "  update:              iterative mean of all throws since the last reset\n";
  } else {
    out << "  update:              iterative mean, gain never below 1/" << settings.window
        << " (forgets throws older than about " << settings.window << ")\n";
  }
  out << format("  target energy E*:    %.4f J (m_p g L, eq. 41)\n", settings.target_energy_J);
  out << "  consistent with the history: "
      << (consistency.ok ? std::string("yes") : "NO: " + consistency.problem) << "\n";
}

}  // namespace gs::adaptation
