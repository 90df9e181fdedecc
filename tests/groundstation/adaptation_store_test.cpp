// The durable adaptation store: persistence across reopening, the adapted values in step with the
// history, reset, clear errors on missing, foreign, newer and damaged files, and the acceptance
// test of issue 4: a writer killed with SIGKILL at random points leaves a store that opens, is
// consistent, has no partial row and never loses a committed throw.
#include "groundstation/adaptation/adaptation_store.hpp"

#include <signal.h>
#include <sqlite3.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "adaptation_test_support.hpp"
#include "groundstation/model/impact.hpp"

namespace {

using namespace gs::adaptation;
using adaptation_test::make_identification;
using adaptation_test::make_record;
using adaptation_test::same_identification;
using adaptation_test::same_record;
using adaptation_test::ScratchDir;

AdaptationSettings test_settings(int window = 0) {
  AdaptationSettings s;
  s.nominal_catch_height_m = 1.40;
  s.nominal_waiting_xy_m = {0.70, 0.05};
  s.window = window;
  s.target_energy_J = gs::model::upright_energy_J(gs::model::PoleParams{});
  return s;
}

std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << bytes;
}

// Runs raw SQL on a file with SQLite itself (to make foreign or newer files).
void raw_sql(const std::string& path, const char* sql) {
  sqlite3* db = nullptr;
  REQUIRE(sqlite3_open(path.c_str(), &db) == SQLITE_OK);
  char* message = nullptr;
  const int rc = sqlite3_exec(db, sql, nullptr, nullptr, &message);
  INFO((message ? message : ""));
  sqlite3_free(message);
  sqlite3_close(db);
  REQUIRE(rc == SQLITE_OK);
}

std::string open_error(const std::string& path) {
  try {
    AdaptationStore::open_existing(path);
  } catch (const StoreError& e) {
    return e.what();
  }
  return "(opened without error)";
}

// Fills a store with `n` throws and closes it (the WAL is checkpointed into the file on close).
void fill(const std::string& path, int n, const AdaptationSettings& settings = test_settings()) {
  AdaptationStore store = AdaptationStore::open_or_create(path, settings);
  for (int id = 1; id <= n; ++id) store.record(make_record(id));
}

}  // namespace

TEST_CASE("a new store holds the nominal values, and throws and values survive reopening") {
  ScratchDir dir("adaptation-store");
  const std::string path = dir.file("store.sqlite");
  const AdaptationSettings settings = test_settings(3);
  std::vector<ThrowRecord> records;
  AdaptationState expected = initial_adaptation(settings);
  {
    AdaptationStore store = AdaptationStore::open_or_create(path, settings);
    const AdaptationSnapshot empty = store.adaptation();
    CHECK(empty.state == initial_adaptation(settings));
    CHECK(empty.throw_count == 0);
    CHECK(empty.last_throw_id == 0);
    for (int id = 1; id <= 30; ++id) {
      records.push_back(make_record(id));
      const StoredThrow stored = store.record(records.back());
      expected = adapt(expected, records.back(), settings.window);
      REQUIRE(stored.id == id);
      REQUIRE(store.adaptation().state == expected);
      if (records.back().energy_after_impact_J) {
        REQUIRE(stored.energy_error_J ==
                std::abs(*records.back().energy_after_impact_J - settings.target_energy_J));
      } else {
        REQUIRE_FALSE(stored.energy_error_J);
      }
    }
  }
  // Reopened (by the CLI's way in), everything is there, bit for bit.
  const AdaptationStore store = AdaptationStore::open_existing(path);
  const AdaptationSettings reread = store.settings();
  CHECK(reread.nominal_catch_height_m == settings.nominal_catch_height_m);
  CHECK(reread.nominal_waiting_xy_m == settings.nominal_waiting_xy_m);
  CHECK(reread.window == settings.window);
  CHECK(reread.target_energy_J == settings.target_energy_J);
  const AdaptationSnapshot snap = store.adaptation();
  CHECK(snap.state == expected);
  CHECK(snap.throw_count == 30);
  CHECK(snap.last_throw_id == 30);
  CHECK(snap.epoch_first_id == 1);
  const std::vector<StoredThrow> history = store.history();
  REQUIRE(history.size() == records.size());
  for (std::size_t i = 0; i < records.size(); ++i) {
    INFO("throw " << i + 1);
    CHECK(history[i].id == static_cast<std::int64_t>(i + 1));
    CHECK(same_record(history[i].record, records[i]));
  }
  const ConsistencyReport report = store.check_consistency();
  INFO(report.problem);
  CHECK(report.ok);
  CHECK(report.recomputed == expected);

  // The last N, oldest first.
  const std::vector<StoredThrow> last = store.history(4);
  REQUIRE(last.size() == 4);
  CHECK(last.front().id == 27);
  CHECK(last.back().id == 30);
  CHECK(store.history(100).size() == 30);
  CHECK(store.history(0).empty());

  // Opening an existing store keeps its own settings.
  AdaptationSettings other = test_settings(0);
  other.nominal_catch_height_m = 2.0;
  CHECK(AdaptationStore::open_or_create(path, other).settings().nominal_catch_height_m == 1.40);
}

TEST_CASE("reset returns to the nominal values and later values rest on later throws only") {
  ScratchDir dir("adaptation-reset");
  const std::string path = dir.file("store.sqlite");
  const AdaptationSettings settings = test_settings();
  {
    AdaptationStore store = AdaptationStore::open_or_create(path, settings);
    for (int id = 1; id <= 10; ++id) store.record(make_record(id));
    REQUIRE(store.adaptation().state.catch_point_samples > 0);
    store.reset();
    const AdaptationSnapshot after = store.adaptation();
    CHECK(after.state == initial_adaptation(settings));
    CHECK(after.epoch_first_id == 11);
    CHECK(after.throw_count == 10);  // the history is kept
    for (int id = 11; id <= 16; ++id) store.record(make_record(id));
  }
  const AdaptationStore store = AdaptationStore::open_existing(path);
  std::vector<ThrowRecord> later;
  for (int id = 11; id <= 16; ++id) later.push_back(make_record(id));
  CHECK(store.adaptation().state == recompute_adaptation(settings, later));
  CHECK(store.history().size() == 16);
  CHECK(store.check_consistency().ok);
}

TEST_CASE("an invalid record is rejected and nothing is written") {
  ScratchDir dir("adaptation-invalid");
  const std::string path = dir.file("store.sqlite");
  AdaptationStore store = AdaptationStore::open_or_create(path, test_settings());
  store.record(make_record(1));
  const AdaptationSnapshot before = store.adaptation();
  ThrowRecord bad = make_record(2);
  bad.catch_height_used_m = std::nan("");
  CHECK_THROWS_WITH(store.record(bad), Catch::Contains("catch_height_used_m is not finite") &&
                                           Catch::Contains("nothing written"));
  CHECK(store.adaptation().state == before.state);
  CHECK(store.throw_count() == 1);
  CHECK_THROWS_AS(AdaptationStore::open_or_create(dir.file("other.sqlite"),
                                                  [] {
                                                    AdaptationSettings s = test_settings();
                                                    s.target_energy_J = 0.0;
                                                    return s;
                                                  }()),
                  StoreError);
}

TEST_CASE("identifications are kept per vehicle, survive reopening, and the last accepted is found") {
  ScratchDir dir("adaptation-identifications");
  const std::string path = dir.file("store.sqlite");
  std::vector<IdentificationRecord> records;
  {
    AdaptationStore store = AdaptationStore::open_or_create(path, test_settings());
    CHECK(store.identification_count() == 0);
    CHECK_FALSE(store.last_accepted_identification(pa::kVehicle1));
    CHECK(store.identifications_by_vehicle().empty());
    for (int id = 1; id <= 9; ++id) {
      records.push_back(make_identification(id));
      REQUIRE(store.record_identification(records.back()).id == id);
    }
    store.record(make_record(1));  // throws and identifications side by side
  }
  const AdaptationStore store = AdaptationStore::open_existing(path);
  const std::vector<StoredIdentification> all = store.identifications();
  REQUIRE(all.size() == records.size());
  for (std::size_t i = 0; i < records.size(); ++i) {
    INFO("identification " << i + 1);
    CHECK(all[i].id == static_cast<std::int64_t>(i + 1));
    CHECK(same_identification(all[i].record, records[i]));
  }
  CHECK(store.identification_count() == 9);
  CHECK(store.throw_count() == 1);
  const std::vector<StoredIdentification> last = store.identifications(3);
  REQUIRE(last.size() == 3);
  CHECK(last.front().id == 7);
  CHECK(last.back().id == 9);

  // Vehicle 1's latest (9) was refused: its last accepted is 7. Vehicle 2's is 8.
  REQUIRE_FALSE(all[8].accepted());
  const std::optional<StoredIdentification> one = store.last_accepted_identification(pa::kVehicle1);
  REQUIRE(one);
  CHECK(one->id == 7);
  CHECK(same_identification(one->record, records[6]));
  CHECK(store.last_accepted_identification(pa::kVehicle2)->id == 8);
  CHECK_FALSE(store.last_accepted_identification(pa::VehicleId(5)));

  const std::vector<VehicleIdentifications> by_vehicle = store.identifications_by_vehicle();
  REQUIRE(by_vehicle.size() == 2);
  CHECK(by_vehicle[0].vehicle == pa::kVehicle1);
  CHECK(by_vehicle[0].count == 5);
  CHECK(by_vehicle[0].latest.id == 9);
  CHECK(by_vehicle[0].last_accepted->id == 7);
  CHECK(by_vehicle[1].vehicle == pa::kVehicle2);
  CHECK(by_vehicle[1].count == 4);
  CHECK(by_vehicle[1].latest.id == 8);
  CHECK(by_vehicle[1].last_accepted->id == 8);

  const ConsistencyReport report = store.check_consistency();
  INFO(report.problem);
  CHECK(report.ok);
}

TEST_CASE("an invalid identification is rejected with the reason and nothing is written") {
  ScratchDir dir("adaptation-identification-invalid");
  AdaptationStore store = AdaptationStore::open_or_create(dir.file("store.sqlite"), test_settings());
  store.record_identification(make_identification(1));
  const auto rejected = [&](IdentificationRecord r, const std::string& reason) {
    INFO(reason);
    CHECK_THROWS_WITH(store.record_identification(r), Catch::Contains(reason) &&
                                                          Catch::Contains("nothing written") &&
                                                          Catch::Contains("store.sqlite"));
    CHECK(store.identification_count() == 1);
  };
  const IdentificationRecord good = make_identification(1);
  REQUIRE(good.result.identified);
  IdentificationRecord r = good;
  r.result.identified->time_constant_s = std::nan("");
  rejected(r, "time_constant_s is not finite");
  r = good;
  r.result.identified->round_trip_s = -0.001;
  rejected(r, "round_trip_s is negative");
  r = good;
  r.result.identified->inertia_gain = std::numeric_limits<double>::infinity();
  rejected(r, "inertia_gain is not finite");
  r = good;
  r.result.identified->time_constant_high_s = 0.5 * r.result.identified->time_constant_s;
  rejected(r, "the 95 % interval does not hold time_constant_s");
  r = good;
  r.thrust_gain = -1.0;
  rejected(r, "thrust_gain is negative");
  r = good;
  r.thrust_gain = std::nan("");
  rejected(r, "thrust_gain is not finite");
  r = good;
  r.time_s = std::nan("");
  rejected(r, "time_s is not finite");
  r = good;
  r.vehicle = pa::VehicleId(pa::proto::kGroundNode);
  rejected(r, "is not a vehicle's node");
  r = good;
  r.result.refusal = gs::estimation::IdentificationRefusal::no_motion;
  rejected(r, "a refused identification carries a fit");
  r = good;
  r.result.identified.reset();
  rejected(r, "an accepted identification carries no fit");
  CHECK(store.check_consistency().ok);
}

// make_record(id) as a store before schema 3 kept it: without its thrower.
ThrowRecord without_thrower(std::int64_t id) {
  ThrowRecord r = make_record(id);
  r.thrower.reset();
  return r;
}

TEST_CASE("a schema-1 store opens, gains the identifications table and keeps everything else") {
  ScratchDir dir("adaptation-migration");
  for (const bool by_the_cli : {true, false}) {
    INFO((by_the_cli ? "open_existing" : "open_or_create"));
    const std::string path = dir.file(by_the_cli ? "cli.sqlite" : "mission.sqlite");
    fill(path, 12);
    // Schema 1 is schema 2 without the identifications, schema 2 schema 3 without the thrower.
    raw_sql(path,
            "DROP TABLE identifications; ALTER TABLE throws DROP COLUMN thrower; PRAGMA user_version = 1");
    const auto schema_has = [&](const char* name) {
      sqlite3* db = nullptr;
      REQUIRE(sqlite3_open(path.c_str(), &db) == SQLITE_OK);
      sqlite3_stmt* st = nullptr;
      REQUIRE(sqlite3_prepare_v2(db, "SELECT count(*) FROM sqlite_schema WHERE name = ?1", -1, &st,
                                 nullptr) == SQLITE_OK);
      sqlite3_bind_text(st, 1, name, -1, SQLITE_STATIC);
      REQUIRE(sqlite3_step(st) == SQLITE_ROW);
      const bool has = sqlite3_column_int(st, 0) == 1;
      sqlite3_finalize(st);
      sqlite3_close(db);
      return has;
    };
    REQUIRE_FALSE(schema_has("identifications"));
    const AdaptationSnapshot before = [&] {
      // Read the old file's values with a store opened on a copy (opening migrates).
      const std::string copy = path + ".copy";
      std::filesystem::copy_file(path, copy);
      return AdaptationStore::open_existing(copy).adaptation();
    }();
    {
      AdaptationStore store = by_the_cli ? AdaptationStore::open_existing(path)
                                         : AdaptationStore::open_or_create(path, test_settings());
      CHECK(store.identification_count() == 0);
      CHECK(store.throw_count() == 12);
      CHECK(store.adaptation().state == before.state);
      for (int id = 1; id <= 12; ++id)
        CHECK(same_record(store.history()[id - 1].record, without_thrower(id)));
      store.record_identification(make_identification(1));
      store.record(make_record(13));  // now with its thrower
      CHECK(same_record(store.history().back().record, make_record(13)));
      CHECK(store.check_consistency().ok);
    }
    CHECK(schema_has("identifications"));
    CHECK(schema_has("identifications_by_vehicle"));
    sqlite3* db = nullptr;
    REQUIRE(sqlite3_open(path.c_str(), &db) == SQLITE_OK);
    sqlite3_stmt* st = nullptr;
    REQUIRE(sqlite3_prepare_v2(db, "PRAGMA user_version", -1, &st, nullptr) == SQLITE_OK);
    REQUIRE(sqlite3_step(st) == SQLITE_ROW);
    CHECK(sqlite3_column_int(st, 0) == kSchemaVersion);
    sqlite3_finalize(st);
    sqlite3_close(db);
    // Reopened: migrated once, the identification kept.
    CHECK(AdaptationStore::open_existing(path).identification_count() == 1);
  }
}

TEST_CASE("missing, empty, foreign, newer and damaged files give a clear error, not a crash") {
  ScratchDir dir("adaptation-bad-files");

  SECTION("missing: an error, and no file is created") {
    const std::string path = dir.file("missing.sqlite");
    CHECK_THAT(open_error(path), Catch::Contains("does not exist") && Catch::Contains(path));
    CHECK_FALSE(std::filesystem::exists(path));
  }
  SECTION("a directory") { CHECK_THAT(open_error(dir.file("")), Catch::Contains("directory")); }
  SECTION("empty: not a store for the CLI; initialised by open_or_create (an interrupted creation)") {
    const std::string path = dir.file("empty.sqlite");
    write_bytes(path, "");
    CHECK_THAT(open_error(path), Catch::Contains("empty database"));
    AdaptationStore store = AdaptationStore::open_or_create(path, test_settings());
    CHECK(store.throw_count() == 0);
    CHECK(store.check_consistency().ok);
  }
  SECTION("a text file") {
    const std::string path = dir.file("notes.txt");
    const std::string text = std::string(3000, 'x') + "\nthis is not a database\n";
    write_bytes(path, text);
    CHECK_THAT(open_error(path),
               Catch::Contains("not an adaptation store") && Catch::Contains("not a SQLite database"));
    CHECK_THROWS_AS(AdaptationStore::open_or_create(path, test_settings()), StoreError);
    CHECK(read_bytes(path) == text);  // left alone
  }
  SECTION("another application's SQLite database") {
    const std::string path = dir.file("foreign.sqlite");
    raw_sql(path, "CREATE TABLE photos (id INTEGER PRIMARY KEY, name TEXT);"
                  "INSERT INTO photos (name) VALUES ('arena.jpg');");
    const std::string before = read_bytes(path);
    CHECK_THAT(open_error(path), Catch::Contains("another application"));
    CHECK_THROWS_WITH(AdaptationStore::open_or_create(path, test_settings()),
                      Catch::Contains("another application"));
    CHECK(read_bytes(path) == before);
  }
  SECTION("a newer schema") {
    const std::string path = dir.file("newer.sqlite");
    fill(path, 3);
    raw_sql(path, ("PRAGMA user_version = " + std::to_string(kSchemaVersion + 1)).c_str());
    CHECK_THAT(open_error(path), Catch::Contains("schema version " + std::to_string(kSchemaVersion + 1)) &&
                                     Catch::Contains("newer"));
  }
  SECTION("a missing table") {
    const std::string path = dir.file("no-table.sqlite");
    fill(path, 3);
    raw_sql(path, "DROP TABLE throws");
    CHECK_THAT(open_error(path), Catch::Contains("damaged") && Catch::Contains("throws"));
  }
  SECTION("pages overwritten in the middle of the file") {
    const std::string path = dir.file("scribbled.sqlite");
    fill(path, 200);
    std::string bytes = read_bytes(path);
    REQUIRE(bytes.size() > 8 * 4096);
    std::mt19937 rng(1);
    for (std::size_t i = 2 * 4096; i < 5 * 4096; ++i) bytes[i] = static_cast<char>(rng());
    write_bytes(path, bytes);
    const std::string message = open_error(path);
    CHECK_THAT(message, Catch::Contains("damaged") && Catch::Contains(path));
  }
  SECTION("truncated to half its length") {
    const std::string path = dir.file("truncated.sqlite");
    fill(path, 200);
    const std::string bytes = read_bytes(path);
    write_bytes(path, bytes.substr(0, bytes.size() / 2));
    CHECK_THAT(open_error(path), Catch::Contains("damaged"));
  }
}

namespace {

// The writer of the kill test: records throws (each a complete throw plus the adapted values, one
// transaction), now and then resetting, until it is killed. Never returns.
[[noreturn]] void writer_child(const std::string& path, const AdaptationSettings& settings) {
  try {
    AdaptationStore store = AdaptationStore::open_or_create(path, settings);
    for (;;) {
      const std::int64_t id = store.throw_count() + 1;
      if (store.record(make_record(id)).id != id) ::_exit(4);
      if (id % 9 == 0) store.reset();
    }
  } catch (...) {
    ::_exit(3);
  }
}

}  // namespace

TEST_CASE("kill -9 during writes: the store opens, is consistent and loses no committed throw") {
  ScratchDir dir("adaptation-kill");
  const std::string path = dir.file("store.sqlite");
  const AdaptationSettings settings = test_settings(4);

  // The kill delays span the time a writer needs to open the store and record a few throws on
  // this machine, so the kills land before, inside and between transactions.
  double open_us = 0.0;
  double record_us = 0.0;
  {
    const std::string scratch = dir.file("calibration.sqlite");
    const auto t0 = std::chrono::steady_clock::now();
    AdaptationStore store = AdaptationStore::open_or_create(scratch, settings);
    const auto t1 = std::chrono::steady_clock::now();
    for (int id = 1; id <= 10; ++id) store.record(make_record(id));
    const auto t2 = std::chrono::steady_clock::now();
    open_us = std::chrono::duration<double, std::micro>(t1 - t0).count();
    record_us = std::chrono::duration<double, std::micro>(t2 - t1).count() / 10.0;
  }
  // On a loaded machine the writer may not even get to run before the kill: until a throw has
  // been committed, each round widens the span for the next one (up to 1 s), so the kills come
  // to land on a working writer however busy the machine is.
  double max_delay_us = std::clamp(open_us + 6.0 * record_us, 2000.0, 50000.0);

  std::mt19937 rng(20130506);
  constexpr int kRounds = 50;
  std::int64_t previous_count = 0;
  int rounds_with_hot_wal = 0;
  int rounds_with_progress = 0;
  for (int round = 0; round < kRounds; ++round) {
    INFO("round " << round);
    std::fflush(nullptr);  // nothing buffered is written twice by the child
    const pid_t child = ::fork();
    REQUIRE(child >= 0);
    if (child == 0) writer_child(path, settings);
    std::uniform_int_distribution<int> delay_us(0, static_cast<int>(max_delay_us));
    std::this_thread::sleep_for(std::chrono::microseconds(delay_us(rng)));
    REQUIRE(::kill(child, SIGKILL) == 0);
    int status = 0;
    REQUIRE(::waitpid(child, &status, 0) == child);
    INFO("writer exit status " << (WIFEXITED(status) ? WEXITSTATUS(status) : -1));
    REQUIRE(WIFSIGNALED(status));
    REQUIRE(WTERMSIG(status) == SIGKILL);

    std::error_code ec;
    if (std::filesystem::file_size(path + "-wal", ec) > 0 && !ec) ++rounds_with_hot_wal;

    // Reopened as the mission would after the crash: no exception, consistent, nothing partial.
    AdaptationStore store = AdaptationStore::open_or_create(path, settings);
    const ConsistencyReport report = store.check_consistency();
    INFO(report.problem);
    REQUIRE(report.ok);
    const std::vector<StoredThrow> history = store.history();
    const auto count = static_cast<std::int64_t>(history.size());
    REQUIRE(count >= previous_count);
    for (const StoredThrow& t : history) {
      INFO("throw " << t.id);
      REQUIRE(same_record(t.record, make_record(t.id)));
    }
    if (count > previous_count) ++rounds_with_progress;
    if (count == 0) max_delay_us = std::min(1.3 * max_delay_us, 1e6);
    previous_count = count;
  }
  std::printf("kill -9 test: %d rounds, kills after 0..%.0f us at the end (open %.0f us, record %.0f us);"
              " %lld throws committed, %d rounds added throws, %d left a hot WAL to recover\n",
              kRounds, max_delay_us, open_us, record_us, static_cast<long long>(previous_count),
              rounds_with_progress, rounds_with_hot_wal);
  // The writers got throws in, so the kills did interrupt a working writer.
  CHECK(previous_count > 0);
}

namespace {

// A VFS shim for the writer child: forwards everything to the default (unix) VFS, counts the
// calls that change files (write, truncate, sync, delete) and sends itself SIGKILL just before the
// k-th one. Killed there, the files hold exactly the writes before it (a killed process loses
// nothing the kernel already has), so sweeping k crashes the writer at every write boundary of
// its transactions, independent of timing.
namespace crash_vfs {

sqlite3_vfs* g_real = nullptr;
sqlite3_vfs g_vfs;
long g_events = 0;
long g_kill_at = 0;  // 0: never

void event() {
  if (g_kill_at > 0 && ++g_events >= g_kill_at) ::raise(SIGKILL);
}

struct File {
  sqlite3_file base;
  sqlite3_file* real() { return reinterpret_cast<sqlite3_file*>(this + 1); }
};
sqlite3_file* real(sqlite3_file* f) { return reinterpret_cast<File*>(f)->real(); }

int xClose(sqlite3_file* f) { return real(f)->pMethods->xClose(real(f)); }
int xRead(sqlite3_file* f, void* b, int n, sqlite3_int64 o) {
  return real(f)->pMethods->xRead(real(f), b, n, o);
}
int xWrite(sqlite3_file* f, const void* b, int n, sqlite3_int64 o) {
  event();
  return real(f)->pMethods->xWrite(real(f), b, n, o);
}
int xTruncate(sqlite3_file* f, sqlite3_int64 size) {
  event();
  return real(f)->pMethods->xTruncate(real(f), size);
}
int xSync(sqlite3_file* f, int flags) {
  event();
  return real(f)->pMethods->xSync(real(f), flags);
}
int xFileSize(sqlite3_file* f, sqlite3_int64* size) { return real(f)->pMethods->xFileSize(real(f), size); }
int xLock(sqlite3_file* f, int l) { return real(f)->pMethods->xLock(real(f), l); }
int xUnlock(sqlite3_file* f, int l) { return real(f)->pMethods->xUnlock(real(f), l); }
int xCheckReservedLock(sqlite3_file* f, int* out) {
  return real(f)->pMethods->xCheckReservedLock(real(f), out);
}
int xFileControl(sqlite3_file* f, int op, void* arg) {
  return real(f)->pMethods->xFileControl(real(f), op, arg);
}
int xSectorSize(sqlite3_file* f) { return real(f)->pMethods->xSectorSize(real(f)); }
int xDeviceCharacteristics(sqlite3_file* f) { return real(f)->pMethods->xDeviceCharacteristics(real(f)); }
int xShmMap(sqlite3_file* f, int page, int size, int extend, void volatile** p) {
  return real(f)->pMethods->xShmMap(real(f), page, size, extend, p);
}
int xShmLock(sqlite3_file* f, int offset, int n, int flags) {
  return real(f)->pMethods->xShmLock(real(f), offset, n, flags);
}
void xShmBarrier(sqlite3_file* f) { real(f)->pMethods->xShmBarrier(real(f)); }
int xShmUnmap(sqlite3_file* f, int remove) { return real(f)->pMethods->xShmUnmap(real(f), remove); }
int xFetch(sqlite3_file* f, sqlite3_int64 o, int n, void** p) {
  return real(f)->pMethods->xFetch(real(f), o, n, p);
}
int xUnfetch(sqlite3_file* f, sqlite3_int64 o, void* p) { return real(f)->pMethods->xUnfetch(real(f), o, p); }

const sqlite3_io_methods kMethods = {3,
                                     xClose,
                                     xRead,
                                     xWrite,
                                     xTruncate,
                                     xSync,
                                     xFileSize,
                                     xLock,
                                     xUnlock,
                                     xCheckReservedLock,
                                     xFileControl,
                                     xSectorSize,
                                     xDeviceCharacteristics,
                                     xShmMap,
                                     xShmLock,
                                     xShmBarrier,
                                     xShmUnmap,
                                     xFetch,
                                     xUnfetch};

int xOpen(sqlite3_vfs*, const char* name, sqlite3_file* f, int flags, int* out_flags) {
  File* file = reinterpret_cast<File*>(f);
  file->base.pMethods = nullptr;
  const int rc = g_real->xOpen(g_real, name, file->real(), flags, out_flags);
  if (file->real()->pMethods != nullptr) file->base.pMethods = &kMethods;
  return rc;
}
int xDelete(sqlite3_vfs*, const char* name, int sync_dir) {
  event();
  return g_real->xDelete(g_real, name, sync_dir);
}

// In the child only: every connection opened from now on goes through the shim.
void install(long kill_at) {
  g_real = sqlite3_vfs_find(nullptr);
  g_vfs = *g_real;
  g_vfs.zName = "crash_vfs";
  g_vfs.szOsFile = static_cast<int>(sizeof(File)) + g_real->szOsFile;
  g_vfs.xOpen = xOpen;
  g_vfs.xDelete = xDelete;
  g_vfs.pNext = nullptr;
  g_events = 0;
  g_kill_at = kill_at;
  sqlite3_vfs_register(&g_vfs, 1);
}

}  // namespace crash_vfs

// Kills a writer child at its k-th file-changing call and checks the reopened store. Returns the
// throw count after the crash.
std::int64_t crash_at_event_and_check(const std::string& path, const AdaptationSettings& settings,
                                      long kill_at, std::int64_t previous_count) {
  std::fflush(nullptr);
  const pid_t child = ::fork();
  REQUIRE(child >= 0);
  if (child == 0) {
    crash_vfs::install(kill_at);
    writer_child(path, settings);
  }
  int status = 0;
  REQUIRE(::waitpid(child, &status, 0) == child);
  INFO("writer exit status " << (WIFEXITED(status) ? WEXITSTATUS(status) : -1));
  REQUIRE(WIFSIGNALED(status));
  REQUIRE(WTERMSIG(status) == SIGKILL);
  AdaptationStore store = AdaptationStore::open_or_create(path, settings);
  const ConsistencyReport report = store.check_consistency();
  INFO(report.problem);
  REQUIRE(report.ok);
  const std::vector<StoredThrow> history = store.history();
  const auto count = static_cast<std::int64_t>(history.size());
  REQUIRE(count >= previous_count);
  for (const StoredThrow& t : history) {
    INFO("throw " << t.id);
    REQUIRE(same_record(t.record, make_record(t.id)));
  }
  return count;
}

}  // namespace

TEST_CASE("SIGKILL at every write boundary of creation, record and reset leaves a sound store") {
  ScratchDir dir("adaptation-crashpoints");
  const AdaptationSettings settings = test_settings(2);

  // Creation and the first throws of a new file, killed at each write in turn until a throw got
  // through: the interrupted creation must leave a file that open_or_create initialises.
  const std::string fresh = dir.file("fresh.sqlite");
  long first_with_throw = 0;
  for (long k = 1; k <= 200 && first_with_throw == 0; ++k) {
    INFO("fresh store, killed at write " << k);
    std::filesystem::remove(fresh);
    std::filesystem::remove(fresh + "-wal");
    std::filesystem::remove(fresh + "-shm");
    if (crash_at_event_and_check(fresh, settings, k, 0) > 0) first_with_throw = k;
  }
  REQUIRE(first_with_throw > 0);

  // A populated store, the writer killed at write 1, 2, 3, ... of its run: every boundary of
  // several records and resets, each from the state the previous crash left.
  const std::string path = dir.file("store.sqlite");
  fill(path, 5, settings);
  std::int64_t count = 5;
  int committed_rounds = 0;
  constexpr long kSweep = 60;
  for (long k = 1; k <= kSweep; ++k) {
    INFO("populated store, killed at write " << k);
    const std::int64_t after = crash_at_event_and_check(path, settings, k, count);
    if (after > count) ++committed_rounds;
    count = after;
  }
  std::printf("crash points: a new store first holds a throw when killed at write %ld; "
              "%ld crash points on a populated store (%d rounds added throws), %lld throws\n",
              first_with_throw, kSweep, committed_rounds, static_cast<long long>(count));
  CHECK(committed_rounds > 0);
}
