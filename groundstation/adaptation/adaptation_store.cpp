#include "groundstation/adaptation/adaptation_store.hpp"

#include <sqlite3.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string_view>
#include <utility>

namespace gs::adaptation {

// ---------------------------------------------------------------------------------------------
// A thin RAII layer over the SQLite C API. Every failure becomes a StoreError naming the file.

struct AdaptationStore::Impl {
  std::string path;
  sqlite3* db = nullptr;
  ~Impl() {
    if (db != nullptr) sqlite3_close_v2(db);
  }
};

namespace {

using Impl = AdaptationStore::Impl;

std::string file_name(const std::string& path) { return "'" + path + "'"; }

[[noreturn]] void fail(const Impl& s, const std::string& what, int rc) {
  const std::string sqlite_says = s.db != nullptr ? sqlite3_errmsg(s.db) : sqlite3_errstr(rc);
  switch (rc & 0xff) {
    case SQLITE_NOTADB:
      throw StoreError(file_name(s.path) + " is not an adaptation store: it is not a SQLite database (" +
                       sqlite_says + ")");
    case SQLITE_CORRUPT:
      throw StoreError("adaptation store " + file_name(s.path) + " is damaged: SQLite reports '" +
                       sqlite_says + "'");
    default:
      throw StoreError("adaptation store " + file_name(s.path) + ": " + what + " (" + sqlite_says + ")");
  }
}

[[noreturn]] void damaged(const Impl& s, const std::string& what) {
  throw StoreError("adaptation store " + file_name(s.path) + " is damaged: " + what);
}

// A record that fails its validate() is refused before anything is written.
template <typename Record>
void require_valid(const Impl& s, const Record& record, const char* what) {
  if (const std::string problem = validate(record); !problem.empty()) {
    throw StoreError("adaptation store " + file_name(s.path) + ": invalid " + what +
                     ", nothing written: " + problem);
  }
}

class Statement {
 public:
  Statement(const Impl& store, std::string_view sql) : store_(store) {
    const int rc = sqlite3_prepare_v2(store.db, sql.data(), static_cast<int>(sql.size()), &stmt_, nullptr);
    if (rc != SQLITE_OK) fail(store, "cannot prepare '" + std::string(sql.substr(0, 40)) + "...'", rc);
  }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;
  ~Statement() { sqlite3_finalize(stmt_); }

  void bind(int index, double value) { check(sqlite3_bind_double(stmt_, index, value)); }
  void bind(int index, std::int64_t value) { check(sqlite3_bind_int64(stmt_, index, value)); }
  void bind(int index, std::string_view text) {
    check(sqlite3_bind_text(stmt_, index, text.data(), static_cast<int>(text.size()), SQLITE_TRANSIENT));
  }
  void bind(int index, const std::optional<double>& value) {
    if (value) {
      bind(index, *value);
    } else {
      check(sqlite3_bind_null(stmt_, index));
    }
  }

  // True when a row is available, false when done.
  bool step() {
    const int rc = sqlite3_step(stmt_);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    fail(store_, "cannot execute '" + std::string(sqlite3_sql(stmt_)).substr(0, 60) + "'", rc);
  }

  bool isNull(int column) const { return sqlite3_column_type(stmt_, column) == SQLITE_NULL; }
  double real(int column) const {
    const int type = sqlite3_column_type(stmt_, column);
    if (type != SQLITE_FLOAT && type != SQLITE_INTEGER) {
      damaged(store_, std::string("column ") + sqlite3_column_name(stmt_, column) + " holds a non-number");
    }
    return sqlite3_column_double(stmt_, column);
  }
  std::optional<double> optional_real(int column) const {
    if (isNull(column)) return std::nullopt;
    return real(column);
  }
  std::int64_t integer(int column) const {
    if (sqlite3_column_type(stmt_, column) != SQLITE_INTEGER) {
      damaged(store_, std::string("column ") + sqlite3_column_name(stmt_, column) + " holds a non-integer");
    }
    return sqlite3_column_int64(stmt_, column);
  }
  std::string text(int column) const {
    const unsigned char* p = sqlite3_column_text(stmt_, column);
    if (p == nullptr) return {};
    return std::string(reinterpret_cast<const char*>(p),
                       static_cast<std::size_t>(sqlite3_column_bytes(stmt_, column)));
  }

 private:
  void check(int rc) {
    if (rc != SQLITE_OK) fail(store_, "cannot bind a value", rc);
  }
  const Impl& store_;
  sqlite3_stmt* stmt_ = nullptr;
};

void exec(const Impl& s, const char* sql) {
  char* message = nullptr;
  const int rc = sqlite3_exec(s.db, sql, nullptr, nullptr, &message);
  if (message != nullptr) sqlite3_free(message);
  if (rc != SQLITE_OK) fail(s, std::string("cannot execute '") + sql + "'", rc);
}

std::int64_t query_integer(const Impl& s, const char* sql) {
  Statement st(s, sql);
  if (!st.step()) damaged(s, std::string("'") + sql + "' returned no row");
  return st.isNull(0) ? 0 : st.integer(0);
}

// BEGIN IMMEDIATE (the write lock is taken up front, so the values read inside are the ones the
// write replaces) or a deferred read transaction; rolled back unless committed.
class Transaction {
 public:
  Transaction(const Impl& s, bool write) : s_(s) { exec(s_, write ? "BEGIN IMMEDIATE" : "BEGIN"); }
  Transaction(const Transaction&) = delete;
  Transaction& operator=(const Transaction&) = delete;
  ~Transaction() {
    if (!done_) sqlite3_exec(s_.db, "ROLLBACK", nullptr, nullptr, nullptr);
  }
  void commit() {
    exec(s_, "COMMIT");
    done_ = true;
  }

 private:
  const Impl& s_;
  bool done_ = false;
};

// The first problem of an integrity or quick check's report (one problem a line, after a
// "*** in database main ***" heading), and how many more there are.
std::string first_problem(const std::string& report) {
  std::vector<std::string> lines;
  std::size_t start = 0;
  while (start <= report.size()) {
    const std::size_t end = report.find('\n', start);
    std::string line = report.substr(start, end == std::string::npos ? end : end - start);
    if (!line.empty() && line.rfind("*** ", 0) != 0) lines.push_back(std::move(line));
    if (end == std::string::npos) break;
    start = end + 1;
  }
  if (lines.empty()) return "'" + report + "'";
  std::string out = "'" + lines.front() + "'";
  if (lines.size() > 1) out += " and " + std::to_string(lines.size() - 1) + " more problems";
  return out;
}

// ---------------------------------------------------------------------------------------------
// Schema 1.

constexpr const char* kCreateSettings = R"sql(
CREATE TABLE settings (
  id INTEGER PRIMARY KEY CHECK (id = 1),
  nominal_catch_height_m REAL NOT NULL,
  nominal_waiting_x_m REAL NOT NULL,
  nominal_waiting_y_m REAL NOT NULL,
  mean_window INTEGER NOT NULL CHECK (mean_window >= 0),
  target_energy_J REAL NOT NULL
) STRICT)sql";

constexpr const char* kCreateAdaptation = R"sql(
CREATE TABLE adaptation (
  id INTEGER PRIMARY KEY CHECK (id = 1),
  catch_height_m REAL NOT NULL,
  waiting_x_m REAL NOT NULL,
  waiting_y_m REAL NOT NULL,
  catch_point_samples INTEGER NOT NULL CHECK (catch_point_samples >= 0),
  offset_bias_x_m REAL NOT NULL,
  offset_bias_y_m REAL NOT NULL,
  bias_samples INTEGER NOT NULL CHECK (bias_samples >= 0),
  last_throw_id INTEGER NOT NULL,
  epoch_first_id INTEGER NOT NULL
) STRICT)sql";

// STRICT tables: SQLite refuses a value of the wrong type instead of storing it. A figure made of
// several columns is either wholly present or wholly NULL.
constexpr const char* kCreateThrowsHead = R"sql(
CREATE TABLE throws (
  id INTEGER PRIMARY KEY,
  time_s REAL NOT NULL,
  outcome TEXT NOT NULL,
  launch_x_m REAL NOT NULL,
  launch_y_m REAL NOT NULL,
  launch_z_m REAL NOT NULL,
  launch_vx_mps REAL NOT NULL,
  launch_vy_mps REAL NOT NULL,
  launch_vz_mps REAL NOT NULL,
  launch_alpha_rad REAL NOT NULL,
  launch_alpha_dot_radps REAL NOT NULL,
  catch_height_used_m REAL NOT NULL,
  waiting_x_m REAL NOT NULL,
  waiting_y_m REAL NOT NULL,
  target_x_m REAL,
  target_y_m REAL,
  predicted_x_m REAL,
  predicted_y_m REAL,
  predicted_t_s REAL,
  actual_x_m REAL,
  actual_y_m REAL,
  actual_t_s REAL,
  optimal_t_s REAL,
  optimal_height_m REAL,
  optimal_x_m REAL,
  optimal_y_m REAL,
  catcher_x_m REAL,
  catcher_y_m REAL,
  energy_J REAL,
  energy_error_J REAL,
  note TEXT NOT NULL,
)sql";

// Schema 3: the throwing vehicle, NULL in throws stored before it (a column constraint, so that
// the migration adds it as it is created).
const std::string kThrowerColumn = "thrower INTEGER CHECK (thrower IS NULL OR thrower BETWEEN " +
                                   std::to_string(pa::proto::kFirstVehicleNode) + " AND " +
                                   std::to_string(pa::proto::kLastVehicleNode) + ")";

constexpr const char* kCreateThrowsChecks = R"sql(
  CHECK ((target_x_m IS NULL) = (target_y_m IS NULL)),
  CHECK ((predicted_x_m IS NULL) = (predicted_y_m IS NULL)
     AND (predicted_x_m IS NULL) = (predicted_t_s IS NULL)),
  CHECK ((actual_x_m IS NULL) = (actual_y_m IS NULL)
     AND (actual_x_m IS NULL) = (actual_t_s IS NULL)),
  CHECK ((optimal_t_s IS NULL) = (optimal_height_m IS NULL)
     AND (optimal_t_s IS NULL) = (optimal_x_m IS NULL)
     AND (optimal_t_s IS NULL) = (optimal_y_m IS NULL)),
  CHECK ((catcher_x_m IS NULL) = (catcher_y_m IS NULL)),
  CHECK ((energy_J IS NULL) = (energy_error_J IS NULL)),
  CHECK (outcome IN ()sql";

// The columns of `throws` in the order bind_throw() and read_throw() use.
constexpr const char* kThrowColumns =
    "id, time_s, outcome, launch_x_m, launch_y_m, launch_z_m, launch_vx_mps, launch_vy_mps, "
    "launch_vz_mps, launch_alpha_rad, launch_alpha_dot_radps, catch_height_used_m, waiting_x_m, "
    "waiting_y_m, target_x_m, target_y_m, predicted_x_m, predicted_y_m, predicted_t_s, "
    "actual_x_m, actual_y_m, actual_t_s, optimal_t_s, optimal_height_m, optimal_x_m, "
    "optimal_y_m, catcher_x_m, catcher_y_m, energy_J, energy_error_J, note, thrower";
constexpr int kThrowColumnCount = 32;

std::string create_throws_sql() {
  std::string sql = std::string(kCreateThrowsHead) + "  " + kThrowerColumn + "," + kCreateThrowsChecks;
  bool first = true;
  for (const ThrowOutcome outcome : kAllThrowOutcomes) {
    sql += first ? "'" : ", '";
    sql += to_string(outcome);
    sql += "'";
    first = false;
  }
  sql += "))\n) STRICT";
  return sql;
}

// ---------------------------------------------------------------------------------------------
// Schema 2: the motor identifications. A fit's columns are wholly present (identified) or wholly
// NULL (refused).

constexpr const char* kCreateIdentificationsHead = R"sql(
CREATE TABLE identifications (
  id INTEGER PRIMARY KEY,
  vehicle INTEGER NOT NULL,
  time_s REAL NOT NULL,
  outcome TEXT NOT NULL,
  time_constant_s REAL CHECK (time_constant_s > 0),
  time_constant_low_s REAL CHECK (time_constant_low_s >= 0),
  time_constant_high_s REAL CHECK (time_constant_high_s >= time_constant_s),
  inertia_gain REAL CHECK (inertia_gain >= 0),
  round_trip_s REAL CHECK (round_trip_s >= 0),
  rms_radps REAL CHECK (rms_radps >= 0),
  samples INTEGER CHECK (samples >= 0),
  thrust_gain REAL CHECK (thrust_gain > 0),
  CHECK ((outcome = 'identified') = (time_constant_s IS NOT NULL)),
  CHECK ((time_constant_s IS NULL) = (time_constant_low_s IS NULL)
     AND (time_constant_s IS NULL) = (time_constant_high_s IS NULL)
     AND (time_constant_s IS NULL) = (inertia_gain IS NULL)
     AND (time_constant_s IS NULL) = (round_trip_s IS NULL)
     AND (time_constant_s IS NULL) = (rms_radps IS NULL)
     AND (time_constant_s IS NULL) = (samples IS NULL)),
)sql";

constexpr const char* kIdentificationColumns =
    "id, vehicle, time_s, outcome, time_constant_s, time_constant_low_s, time_constant_high_s, "
    "inertia_gain, round_trip_s, rms_radps, samples, thrust_gain";

std::string create_identifications_sql() {
  std::string sql = kCreateIdentificationsHead;
  sql += "  CHECK (vehicle BETWEEN " + std::to_string(pa::proto::kFirstVehicleNode) + " AND " +
         std::to_string(pa::proto::kLastVehicleNode) + "),\n  CHECK (outcome IN ('identified'";
  for (const estimation::IdentificationRefusal refusal : estimation::kAllIdentificationRefusals) {
    sql += ", '";
    sql += estimation::refusal_name(refusal);
    sql += "'";
  }
  sql += "))\n) STRICT";
  return sql;
}

constexpr const char* kCreateIdentificationsIndex =
    "CREATE INDEX identifications_by_vehicle ON identifications (vehicle, id)";

void bind_identification(Statement& st, std::int64_t id, const IdentificationRecord& r) {
  const std::optional<estimation::MotorIdentification>& m = r.result.identified;
  const auto fit = [&](double estimation::MotorIdentification::*field) {
    return m ? std::optional<double>((*m).*field) : std::nullopt;
  };
  int i = 1;
  st.bind(i++, id);
  st.bind(i++, static_cast<std::int64_t>(r.vehicle.node()));
  st.bind(i++, r.time_s);
  st.bind(i++, outcome_name(r.result));
  st.bind(i++, fit(&estimation::MotorIdentification::time_constant_s));
  st.bind(i++, fit(&estimation::MotorIdentification::time_constant_low_s));
  st.bind(i++, fit(&estimation::MotorIdentification::time_constant_high_s));
  st.bind(i++, fit(&estimation::MotorIdentification::inertia_gain));
  st.bind(i++, fit(&estimation::MotorIdentification::round_trip_s));
  st.bind(i++, fit(&estimation::MotorIdentification::rms_radps));
  if (m) {
    st.bind(i++, static_cast<std::int64_t>(m->samples));
  } else {
    st.bind(i++, std::optional<double>());
  }
  st.bind(i++, r.thrust_gain);
}

StoredIdentification read_identification(const Impl& s, const Statement& st) {
  StoredIdentification out;
  IdentificationRecord& r = out.record;
  out.id = st.integer(0);
  const std::int64_t node = st.integer(1);
  r.vehicle = pa::VehicleId(static_cast<std::uint8_t>(std::clamp<std::int64_t>(node, 0, 255)));
  if (node != r.vehicle.node() || !r.vehicle.valid()) {
    damaged(s, "identification " + std::to_string(out.id) + " names no vehicle (node " +
                   std::to_string(node) + ")");
  }
  r.time_s = st.real(2);
  const std::string outcome = st.text(3);
  const std::optional<estimation::IdentificationRefusal> refusal = parse_identification_outcome(outcome);
  if (!refusal)
    damaged(s, "identification " + std::to_string(out.id) + " has unknown outcome '" + outcome + "'");
  r.result.refusal = *refusal;
  if (!st.isNull(4)) {
    estimation::MotorIdentification m;
    m.time_constant_s = st.real(4);
    m.time_constant_low_s = st.real(5);
    m.time_constant_high_s = st.real(6);
    m.inertia_gain = st.real(7);
    m.round_trip_s = st.real(8);
    m.rms_radps = st.real(9);
    m.samples = static_cast<int>(st.integer(10));
    r.result.identified = m;
  }
  r.thrust_gain = st.optional_real(11);
  return out;
}

std::optional<double> component(const std::optional<Eigen::Vector2d>& v, int i) {
  if (!v) return std::nullopt;
  return (*v)(i);
}

void bind_throw(Statement& st, std::int64_t id, const ThrowRecord& r,
                const std::optional<double>& energy_error_J) {
  int i = 1;
  st.bind(i++, id);
  st.bind(i++, r.time_s);
  st.bind(i++, to_string(r.outcome));
  st.bind(i++, r.launch.x_m);
  st.bind(i++, r.launch_y_m);
  st.bind(i++, r.launch.z_m);
  st.bind(i++, r.launch.vx_mps);
  st.bind(i++, r.launch_vy_mps);
  st.bind(i++, r.launch.vz_mps);
  st.bind(i++, r.launch.alpha_rad);
  st.bind(i++, r.launch.alpha_dot_radps);
  st.bind(i++, r.catch_height_used_m);
  st.bind(i++, r.waiting_xy_m.x());
  st.bind(i++, r.waiting_xy_m.y());
  st.bind(i++, component(r.target_xy_m, 0));
  st.bind(i++, component(r.target_xy_m, 1));
  const auto predicted_xy = r.predicted ? std::optional(r.predicted->xy_m) : std::nullopt;
  st.bind(i++, component(predicted_xy, 0));
  st.bind(i++, component(predicted_xy, 1));
  st.bind(i++, r.predicted ? std::optional(r.predicted->t_s) : std::nullopt);
  const auto actual_xy = r.actual ? std::optional(r.actual->xy_m) : std::nullopt;
  st.bind(i++, component(actual_xy, 0));
  st.bind(i++, component(actual_xy, 1));
  st.bind(i++, r.actual ? std::optional(r.actual->t_s) : std::nullopt);
  st.bind(i++, r.optimal ? std::optional(r.optimal->t_s) : std::nullopt);
  st.bind(i++, r.optimal ? std::optional(r.optimal->height_m) : std::nullopt);
  const auto optimal_xy = r.optimal ? std::optional(r.optimal->xy_m) : std::nullopt;
  st.bind(i++, component(optimal_xy, 0));
  st.bind(i++, component(optimal_xy, 1));
  st.bind(i++, component(r.catcher_at_impact_xy_m, 0));
  st.bind(i++, component(r.catcher_at_impact_xy_m, 1));
  st.bind(i++, r.energy_after_impact_J);
  st.bind(i++, energy_error_J);
  st.bind(i++, std::string_view(r.note));
  if (r.thrower) {
    st.bind(i++, static_cast<std::int64_t>(r.thrower->node()));
  } else {
    st.bind(i++, std::optional<double>());
  }
}

std::optional<Eigen::Vector2d> read_pair(const Statement& st, int column) {
  if (st.isNull(column)) return std::nullopt;
  return Eigen::Vector2d(st.real(column), st.real(column + 1));
}

StoredThrow read_throw(const Impl& s, const Statement& st) {
  StoredThrow out;
  ThrowRecord& r = out.record;
  out.id = st.integer(0);
  r.time_s = st.real(1);
  const std::string outcome = st.text(2);
  const std::optional<ThrowOutcome> parsed = parse_throw_outcome(outcome);
  if (!parsed) damaged(s, "throw " + std::to_string(out.id) + " has unknown outcome '" + outcome + "'");
  r.outcome = *parsed;
  r.launch.x_m = st.real(3);
  r.launch_y_m = st.real(4);
  r.launch.z_m = st.real(5);
  r.launch.vx_mps = st.real(6);
  r.launch_vy_mps = st.real(7);
  r.launch.vz_mps = st.real(8);
  r.launch.alpha_rad = st.real(9);
  r.launch.alpha_dot_radps = st.real(10);
  r.catch_height_used_m = st.real(11);
  r.waiting_xy_m = Eigen::Vector2d(st.real(12), st.real(13));
  r.target_xy_m = read_pair(st, 14);
  if (const auto xy = read_pair(st, 16)) r.predicted = CatchPoint{*xy, st.real(18)};
  if (const auto xy = read_pair(st, 19)) r.actual = CatchPoint{*xy, st.real(21)};
  if (!st.isNull(22)) r.optimal = OptimalCatch{st.real(22), st.real(23), *read_pair(st, 24)};
  r.catcher_at_impact_xy_m = read_pair(st, 26);
  r.energy_after_impact_J = st.optional_real(28);
  out.energy_error_J = st.optional_real(29);
  r.note = st.text(30);
  if (!st.isNull(31)) {
    const std::int64_t node = st.integer(31);
    const pa::VehicleId thrower(static_cast<std::uint8_t>(std::clamp<std::int64_t>(node, 0, 255)));
    if (node != thrower.node() || !thrower.valid())
      damaged(s, "throw " + std::to_string(out.id) + " names no vehicle as its thrower (node " +
                     std::to_string(node) + ")");
    r.thrower = thrower;
  }
  return out;
}

AdaptationSettings read_settings(const Impl& s) {
  Statement st(s, "SELECT nominal_catch_height_m, nominal_waiting_x_m, nominal_waiting_y_m, "
                  "mean_window, target_energy_J FROM settings WHERE id = 1");
  if (!st.step()) damaged(s, "the settings row is missing");
  AdaptationSettings settings;
  settings.nominal_catch_height_m = st.real(0);
  settings.nominal_waiting_xy_m = Eigen::Vector2d(st.real(1), st.real(2));
  const std::int64_t window = st.integer(3);
  if (window < 0 || window > 1000000000) damaged(s, "the settings hold an invalid window");
  settings.window = static_cast<int>(window);
  settings.target_energy_J = st.real(4);
  if (const std::string problem = validate(settings); !problem.empty()) {
    damaged(s, "invalid settings: " + problem);
  }
  return settings;
}

AdaptationSnapshot read_snapshot(const Impl& s) {
  Statement st(s, "SELECT catch_height_m, waiting_x_m, waiting_y_m, catch_point_samples, "
                  "offset_bias_x_m, offset_bias_y_m, bias_samples, last_throw_id, epoch_first_id, "
                  "(SELECT count(*) FROM throws) FROM adaptation WHERE id = 1");
  if (!st.step()) damaged(s, "the adaptation row is missing");
  AdaptationSnapshot snap;
  snap.state.catch_height_m = st.real(0);
  snap.state.waiting_xy_m = Eigen::Vector2d(st.real(1), st.real(2));
  snap.state.catch_point_samples = st.integer(3);
  snap.state.offset_bias_m = Eigen::Vector2d(st.real(4), st.real(5));
  snap.state.bias_samples = st.integer(6);
  snap.last_throw_id = st.integer(7);
  snap.epoch_first_id = st.integer(8);
  snap.throw_count = st.integer(9);
  return snap;
}

void write_snapshot(const Impl& s, const AdaptationState& a, std::int64_t last_throw_id,
                    std::int64_t epoch_first_id) {
  Statement st(s, "UPDATE adaptation SET catch_height_m = ?1, waiting_x_m = ?2, waiting_y_m = ?3, "
                  "catch_point_samples = ?4, offset_bias_x_m = ?5, offset_bias_y_m = ?6, "
                  "bias_samples = ?7, last_throw_id = ?8, epoch_first_id = ?9 WHERE id = 1");
  st.bind(1, a.catch_height_m);
  st.bind(2, a.waiting_xy_m.x());
  st.bind(3, a.waiting_xy_m.y());
  st.bind(4, a.catch_point_samples);
  st.bind(5, a.offset_bias_m.x());
  st.bind(6, a.offset_bias_m.y());
  st.bind(7, a.bias_samples);
  st.bind(8, last_throw_id);
  st.bind(9, epoch_first_id);
  st.step();
  if (sqlite3_changes(s.db) != 1) damaged(s, "the adaptation row is missing");
}

// The rows of `select_from` (SELECT columns FROM table) read by `read`, with a WHERE, ORDER and
// LIMIT clause and its one parameter.
template <typename Read>
auto read_rows(const Impl& s, const std::string& select_from, const char* where_order_limit,
               std::optional<std::int64_t> parameter, Read read) {
  Statement st(s, select_from + " " + where_order_limit);
  if (parameter) st.bind(1, *parameter);
  std::vector<decltype(read(s, st))> out;
  while (st.step()) out.push_back(read(s, st));
  return out;
}

// All rows in id order, or the last `last_n`.
template <typename Read>
auto last_rows(const Impl& s, const std::string& select_from, std::optional<std::int64_t> last_n, Read read) {
  if (!last_n) return read_rows(s, select_from, "ORDER BY id", std::nullopt, read);
  auto newest_first =
      read_rows(s, select_from, "ORDER BY id DESC LIMIT ?1", std::max<std::int64_t>(*last_n, 0), read);
  return decltype(newest_first)(newest_first.rbegin(), newest_first.rend());
}

std::string select_throws() { return std::string("SELECT ") + kThrowColumns + " FROM throws"; }
std::string select_identifications() {
  return std::string("SELECT ") + kIdentificationColumns + " FROM identifications";
}

std::vector<StoredThrow> read_throws(const Impl& s, const char* where_order_limit,
                                     std::optional<std::int64_t> parameter) {
  return read_rows(s, select_throws(), where_order_limit, parameter, read_throw);
}

bool is_empty_database(const Impl& s) {
  return query_integer(s, "PRAGMA application_id") == 0 && query_integer(s, "PRAGMA user_version") == 0 &&
         query_integer(s, "SELECT count(*) FROM sqlite_schema") == 0;
}

void initialise(const Impl& s, const AdaptationSettings& settings) {
  // WAL cannot be switched inside a transaction; where the file system cannot share memory it
  // stays a rollback journal, which is as atomic.
  exec(s, "PRAGMA journal_mode = WAL");
  Transaction tx(s, true);
  if (!is_empty_database(s)) return;  // another process initialised it first
  exec(s, kCreateSettings);
  exec(s, kCreateAdaptation);
  exec(s, create_throws_sql().c_str());
  exec(s, create_identifications_sql().c_str());
  exec(s, kCreateIdentificationsIndex);
  {
    Statement st(s, "INSERT INTO settings (id, nominal_catch_height_m, nominal_waiting_x_m, "
                    "nominal_waiting_y_m, mean_window, target_energy_J) VALUES (1, ?1, ?2, ?3, ?4, ?5)");
    st.bind(1, settings.nominal_catch_height_m);
    st.bind(2, settings.nominal_waiting_xy_m.x());
    st.bind(3, settings.nominal_waiting_xy_m.y());
    st.bind(4, static_cast<std::int64_t>(settings.window));
    st.bind(5, settings.target_energy_J);
    st.step();
  }
  exec(s, "INSERT INTO adaptation (id, catch_height_m, waiting_x_m, waiting_y_m, "
          "catch_point_samples, offset_bias_x_m, offset_bias_y_m, bias_samples, last_throw_id, "
          "epoch_first_id) VALUES (1, 0, 0, 0, 0, 0, 0, 0, 0, 1)");
  write_snapshot(s, initial_adaptation(settings), 0, 1);
  // The header fields are written by the same transaction: a crash before COMMIT leaves an empty
  // database, which open_or_create() initialises again.
  exec(s, ("PRAGMA application_id = " + std::to_string(kApplicationId)).c_str());
  exec(s, ("PRAGMA user_version = " + std::to_string(kSchemaVersion)).c_str());
  tx.commit();
}

// A file of an older schema brought to this one, in one transaction (another process may have
// done it since the version was read: it is read again under the write lock). Schema 1 -> 2: the
// identifications table; 2 -> 3: the throws' thrower.
void migrate(const Impl& s) {
  Transaction tx(s, true);
  const std::int64_t version = query_integer(s, "PRAGMA user_version");
  if (version >= kSchemaVersion) return;
  if (version < 2) {
    exec(s, create_identifications_sql().c_str());
    exec(s, kCreateIdentificationsIndex);
  }
  if (version < 3) exec(s, ("ALTER TABLE throws ADD COLUMN " + kThrowerColumn).c_str());
  exec(s, ("PRAGMA user_version = " + std::to_string(kSchemaVersion)).c_str());
  tx.commit();
}

// Identity, version and a structural check of an opened file; an older schema is migrated.
void check_identity(const Impl& s) {
  const std::int64_t application_id = query_integer(s, "PRAGMA application_id");
  const std::int64_t version = query_integer(s, "PRAGMA user_version");
  if (application_id != kApplicationId) {
    char hex[16];
    std::snprintf(hex, sizeof hex, "0x%08llx",
                  static_cast<unsigned long long>(static_cast<std::uint32_t>(application_id)));
    throw StoreError(file_name(s.path) +
                     " is not an adaptation store: it is a SQLite database of another application"
                     " (application_id " +
                     hex + ")");
  }
  if (version > kSchemaVersion) {
    throw StoreError("adaptation store " + file_name(s.path) + " has schema version " +
                     std::to_string(version) + ", newer than this program's " +
                     std::to_string(kSchemaVersion) + ": use a newer groundstation");
  }
  if (version < 1) {
    damaged(s, "unknown schema version " + std::to_string(version));
  }
  {
    Statement check(s, "PRAGMA quick_check");
    if (!check.step()) damaged(s, "the quick check returned nothing");
    if (const std::string verdict = check.text(0); verdict != "ok") {
      damaged(s, "SQLite's quick check finds " + first_problem(verdict));
    }
  }
  for (const char* table : {"settings", "adaptation", "throws"}) {
    Statement st(s, "SELECT count(*) FROM sqlite_schema WHERE type = 'table' AND name = ?1");
    st.bind(1, std::string_view(table));
    if (!st.step() || st.integer(0) != 1) damaged(s, std::string("the table ") + table + " is missing");
  }
  if (version < kSchemaVersion) migrate(s);
  for (const char* table : {"identifications"}) {
    Statement st(s, "SELECT count(*) FROM sqlite_schema WHERE type = 'table' AND name = ?1");
    st.bind(1, std::string_view(table));
    if (!st.step() || st.integer(0) != 1) damaged(s, std::string("the table ") + table + " is missing");
  }
  read_settings(s);
  read_snapshot(s);
}

std::unique_ptr<Impl> connect(const std::string& path, bool create) {
  auto s = std::make_unique<Impl>();
  s->path = path;
  std::error_code ec;
  if (!create && !std::filesystem::exists(path, ec)) {
    throw StoreError("no adaptation store at " + file_name(path) + ": the file does not exist");
  }
  if (std::filesystem::is_directory(path, ec)) {
    throw StoreError(file_name(path) + " is a directory, not an adaptation store");
  }
  const int flags = SQLITE_OPEN_READWRITE | (create ? SQLITE_OPEN_CREATE : 0);
  const int rc = sqlite3_open_v2(path.c_str(), &s->db, flags, nullptr);
  if (rc != SQLITE_OK) fail(*s, "cannot open the file", rc);
  sqlite3_extended_result_codes(s->db, 1);
  // A second process (the CLI beside the mission) waits for a write lock instead of failing.
  sqlite3_busy_timeout(s->db, 5000);
  exec(*s, "PRAGMA synchronous = FULL");
  return s;
}

}  // namespace

// ---------------------------------------------------------------------------------------------

AdaptationStore::AdaptationStore(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
AdaptationStore::AdaptationStore(AdaptationStore&&) noexcept = default;
AdaptationStore& AdaptationStore::operator=(AdaptationStore&&) noexcept = default;
AdaptationStore::~AdaptationStore() = default;

AdaptationStore AdaptationStore::open_or_create(const std::string& path, const AdaptationSettings& settings) {
  if (const std::string problem = validate(settings); !problem.empty()) {
    throw StoreError("cannot create adaptation store " + file_name(path) + ": " + problem);
  }
  std::unique_ptr<Impl> s = connect(path, true);
  if (is_empty_database(*s)) initialise(*s, settings);
  check_identity(*s);
  return AdaptationStore(std::move(s));
}

AdaptationStore AdaptationStore::open_existing(const std::string& path) {
  std::unique_ptr<Impl> s = connect(path, false);
  if (is_empty_database(*s)) {
    throw StoreError(file_name(path) + " is not an adaptation store: it is an empty database");
  }
  check_identity(*s);
  return AdaptationStore(std::move(s));
}

const std::string& AdaptationStore::path() const { return impl_->path; }

AdaptationSettings AdaptationStore::settings() const { return read_settings(*impl_); }

AdaptationSnapshot AdaptationStore::adaptation() const {
  Transaction tx(*impl_, false);
  return read_snapshot(*impl_);
}

StoredThrow AdaptationStore::record(const ThrowRecord& record) {
  require_valid(*impl_, record, "throw record");
  const Impl& s = *impl_;
  Transaction tx(s, true);
  const AdaptationSettings settings = read_settings(s);
  const AdaptationSnapshot snap = read_snapshot(s);
  const std::int64_t max_id = query_integer(s, "SELECT max(id) FROM throws");
  if (snap.last_throw_id != max_id) {
    damaged(s, "the adapted values include throw " + std::to_string(snap.last_throw_id) +
                   " but the last throw is " + std::to_string(max_id));
  }
  StoredThrow stored;
  stored.id = max_id + 1;
  stored.record = record;
  if (record.energy_after_impact_J) {
    stored.energy_error_J = std::abs(*record.energy_after_impact_J - settings.target_energy_J);
  }
  {
    Statement st(s, std::string("INSERT INTO throws (") + kThrowColumns +
                        ") VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13, ?14, "
                        "?15, ?16, ?17, ?18, ?19, ?20, ?21, ?22, ?23, ?24, ?25, ?26, ?27, ?28, "
                        "?29, ?30, ?31, ?32)");
    static_assert(kThrowColumnCount == 32);
    bind_throw(st, stored.id, record, stored.energy_error_J);
    st.step();
  }
  write_snapshot(s, adapt(snap.state, record, settings.window), stored.id, snap.epoch_first_id);
  tx.commit();
  return stored;
}

void AdaptationStore::reset() {
  const Impl& s = *impl_;
  Transaction tx(s, true);
  const AdaptationSettings settings = read_settings(s);
  const std::int64_t max_id = query_integer(s, "SELECT max(id) FROM throws");
  write_snapshot(s, initial_adaptation(settings), max_id, max_id + 1);
  tx.commit();
}

std::vector<StoredThrow> AdaptationStore::history(std::optional<std::int64_t> last_n) const {
  return last_rows(*impl_, select_throws(), last_n, read_throw);
}

std::int64_t AdaptationStore::throw_count() const {
  return query_integer(*impl_, "SELECT count(*) FROM throws");
}

StoredIdentification AdaptationStore::record_identification(const IdentificationRecord& record) {
  require_valid(*impl_, record, "identification");
  const Impl& s = *impl_;
  Transaction tx(s, true);
  StoredIdentification stored;
  stored.id = query_integer(s, "SELECT max(id) FROM identifications") + 1;
  stored.record = record;
  {
    Statement st(s, std::string("INSERT INTO identifications (") + kIdentificationColumns +
                        ") VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12)");
    bind_identification(st, stored.id, record);
    st.step();
  }
  tx.commit();
  return stored;
}

std::optional<StoredIdentification> AdaptationStore::last_accepted_identification(
    pa::VehicleId vehicle) const {
  const std::vector<StoredIdentification> rows =
      read_rows(*impl_, select_identifications(),
                "WHERE vehicle = ?1 AND outcome = 'identified' ORDER BY id DESC LIMIT 1",
                static_cast<std::int64_t>(vehicle.node()), read_identification);
  if (rows.empty()) return std::nullopt;
  return rows.front();
}

std::vector<StoredIdentification> AdaptationStore::identifications(std::optional<std::int64_t> last_n) const {
  return last_rows(*impl_, select_identifications(), last_n, read_identification);
}

std::vector<VehicleIdentifications> AdaptationStore::identifications_by_vehicle() const {
  std::map<std::uint8_t, VehicleIdentifications> by_node;
  for (const StoredIdentification& row : identifications()) {
    VehicleIdentifications& v = by_node.try_emplace(row.record.vehicle.node()).first->second;
    v.vehicle = row.record.vehicle;
    v.latest = row;  // rows come oldest first
    if (row.accepted()) v.last_accepted = row;
    ++v.count;
  }
  std::vector<VehicleIdentifications> out;
  for (auto& [node, v] : by_node) out.push_back(std::move(v));
  return out;
}

std::int64_t AdaptationStore::identification_count() const {
  return query_integer(*impl_, "SELECT count(*) FROM identifications");
}

ConsistencyReport AdaptationStore::check_consistency() const {
  const Impl& s = *impl_;
  ConsistencyReport report;
  {
    Statement check(s, "PRAGMA integrity_check");
    if (!check.step()) {
      report.problem = "the integrity check returned nothing";
      return report;
    }
    if (const std::string verdict = check.text(0); verdict != "ok") {
      report.problem = "SQLite's integrity check finds " + first_problem(verdict);
      return report;
    }
  }
  Transaction tx(s, false);
  const AdaptationSettings settings = read_settings(s);
  const AdaptationSnapshot snap = read_snapshot(s);
  const std::int64_t max_id = query_integer(s, "SELECT max(id) FROM throws");
  const std::int64_t min_id = query_integer(s, "SELECT min(id) FROM throws");
  report.stored = snap.state;
  if (snap.throw_count != max_id || (snap.throw_count > 0 && min_id != 1)) {
    report.problem = "the throw ids are not 1.." + std::to_string(snap.throw_count);
    return report;
  }
  if (snap.last_throw_id != max_id) {
    report.problem = "the adapted values include throw " + std::to_string(snap.last_throw_id) +
                     " but the last throw is " + std::to_string(max_id);
    return report;
  }
  if (snap.epoch_first_id < 1 || snap.epoch_first_id > max_id + 1) {
    report.problem = "the adaptation epoch starts at throw " + std::to_string(snap.epoch_first_id) +
                     ", outside 1.." + std::to_string(max_id + 1);
    return report;
  }
  const std::vector<StoredThrow> all = read_throws(s, "ORDER BY id", std::nullopt);
  std::vector<ThrowRecord> records;
  for (const StoredThrow& t : all) {
    if (t.id >= snap.epoch_first_id) records.push_back(t.record);
    const std::optional<double> expected =
        t.record.energy_after_impact_J
            ? std::optional(std::abs(*t.record.energy_after_impact_J - settings.target_energy_J))
            : std::nullopt;
    if (t.energy_error_J != expected) {
      report.problem = "throw " + std::to_string(t.id) + " has an inconsistent |E - E*|";
      return report;
    }
  }
  report.recomputed = recompute_adaptation(settings, records);
  if (!(report.recomputed == report.stored)) {
    report.problem = "the stored adapted values differ from those recomputed from the history";
    return report;
  }
  for (const StoredIdentification& i :
       last_rows(s, select_identifications(), std::nullopt, read_identification)) {
    if (const std::string problem = validate(i.record); !problem.empty()) {
      report.problem = "identification " + std::to_string(i.id) + " is invalid: " + problem;
      return report;
    }
  }
  report.ok = true;
  return report;
}

}  // namespace gs::adaptation
