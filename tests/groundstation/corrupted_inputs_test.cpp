// Issue 13, "no input crashes us": every reader of a file (the motion-capture CSV, the plant,
// scenario and vehicle-limits YAML, the adaptation store) given corrupted and truncated files
// answers with a clear error that names the file and, where the format has lines, the line;
// nothing throws past the reader's contract. The adaptation store loses no committed throw to a
// torn write-ahead log (the file a crash leaves half written), and a truncated or damaged store
// file is refused, not read as a shorter history. tests/fuzz/ fuzzes the same readers.
#include <algorithm>
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "adaptation_test_support.hpp"
#include "groundstation/adaptation/adaptation_store.hpp"
#include "groundstation/estimation/mocap_log.hpp"
#include "groundstation/model/impact.hpp"
#include "groundstation/model/vehicle_limits.hpp"
#include "hil/plant/plant_config.hpp"
#include "hil/plant/scenario.hpp"

namespace {

using adaptation_test::ScratchDir;
using namespace std::string_literals;

std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << bytes;
}

int count_lines(const std::string& text) {
  int lines = 1;
  for (char c : text) lines += c == '\n';
  return lines;
}

// `text` with the value of the top-level key `key` replaced by `value`; `line` is its 1-based line.
std::string replace_value(const std::string& text, const std::string& key, const std::string& value,
                          int& line) {
  std::istringstream in(text);
  std::string out, row;
  line = 0;
  int at = 0;
  while (std::getline(in, row)) {
    ++at;
    if (line == 0 && row.rfind(key + ":", 0) == 0) {
      row = key + ": " + value;
      line = at;
    }
    out += row + '\n';
  }
  REQUIRE(line > 0);
  return out;
}

// "path:line: message" with that line, or any line when `line` is 0.
void check_names_file_and_line(const std::string& error, const std::string& path, int line) {
  INFO(error);
  REQUIRE(error.rfind(path + ":", 0) == 0);
  const std::string rest = error.substr(path.size() + 1);
  std::smatch m;
  REQUIRE(std::regex_search(rest, m, std::regex("^([0-9]+): \\S")));
  if (line > 0) CHECK(std::stoi(m[1]) == line);
}

// "path: message" or "path:line: message" with the line within the text's `lines`.
void check_names_file(const std::string& error, const std::string& path, int lines) {
  INFO(error);
  REQUIRE(error.rfind(path + ":", 0) == 0);
  const std::string rest = error.substr(path.size() + 1);
  std::smatch m;
  if (std::regex_search(rest, m, std::regex("^([0-9]+): \\S"))) {
    CHECK(std::stoi(m[1]) >= 1);
    CHECK(std::stoi(m[1]) <= lines + 1);
  } else {
    CHECK(std::regex_search(rest, std::regex("^ \\S")));
  }
}

// One YAML reader, loading from a file: true when it accepted the file, else `error`.
using YamlLoader = bool (*)(const std::string& path, std::string& error);

bool load_plant(const std::string& path, std::string& error) {
  hil::PlantConfig config;
  return hil::load_plant_config(path, config, error);
}
bool load_scenario_file(const std::string& path, std::string& error) {
  hil::Scenario scenario;
  return hil::load_scenario(path, scenario, error);
}
bool load_limits(const std::string& path, std::string& error) {
  const gs::model::VehicleLimitsLoad load = gs::model::load_vehicle_limits(path);
  error = load.error;
  return load.ok;
}

struct YamlReader {
  const char* what;
  std::string source;     // the shipped file
  std::string key;        // a numeric key of it to corrupt
  std::string file_name;  // where the test writes its copies (in the scratch folder)
  YamlLoader load;
};

std::vector<YamlReader> yaml_readers() {
  const std::string root = PA_SOURCE_DIR;
  return {
      {"plant", root + "/hil/config/plant.yaml", "pole_mass_kg", "plant.yaml", load_plant},
      // In a folder of its own, beside a copy of the plant file it names (in its parent folder).
      {"scenario", root + "/hil/config/scenarios/free_flight_catch.yaml", "duration_s",
       "scenarios/free_flight_catch.yaml", load_scenario_file},
      {"vehicle limits", root + "/groundstation/config/vehicle_limits.yaml", "a_q_max_mps2",
       "vehicle_limits.yaml", load_limits},
  };
}

// A scratch folder holding an intact plant.yaml, so that a scenario's plant_config resolves.
void prepare(const ScratchDir& dir) {
  std::filesystem::create_directories(dir.file("scenarios"));
  std::filesystem::copy_file(std::string(PA_SOURCE_DIR) + "/hil/config/plant.yaml", dir.file("plant.yaml"),
                             std::filesystem::copy_options::overwrite_existing);
}

}  // namespace

TEST_CASE("the YAML readers name the file and the line of a corrupted value or a syntax error",
          "[corrupted]") {
  ScratchDir dir("corrupted-yaml");
  prepare(dir);
  for (const YamlReader& reader : yaml_readers()) {
    INFO(reader.what);
    const std::string text = read_bytes(reader.source);
    // The plant reader is tried on a copy; its own file stays intact for the scenario.
    const std::string path =
        dir.file(reader.file_name == "plant.yaml" ? "plant_copy.yaml" : reader.file_name);
    std::string error;
    write_bytes(path, text);
    REQUIRE(reader.load(path, error));

    int line = 0;
    write_bytes(path, replace_value(text, reader.key, "1.5x", line));
    CHECK_FALSE(reader.load(path, error));
    check_names_file_and_line(error, path, line);
    CHECK_THAT(error, Catch::Contains(reader.key) || Catch::Contains("1.5x"));

    write_bytes(path, replace_value(text, reader.key, "[1.0, 2", line));
    CHECK_FALSE(reader.load(path, error));
    check_names_file_and_line(error, path, 0);

    write_bytes(path, replace_value(text, reader.key, "{unclosed: 1", line));
    CHECK_FALSE(reader.load(path, error));
    check_names_file_and_line(error, path, 0);

    write_bytes(path, text + "\nnot_a_key_of_this_file: 1\n");
    CHECK_FALSE(reader.load(path, error));
    check_names_file_and_line(error, path, count_lines(text) + 1);
  }
}

TEST_CASE("the YAML readers answer every truncation and random damage with a clear error", "[corrupted]") {
  ScratchDir dir("truncated-yaml");
  prepare(dir);
  std::mt19937 rng(13);
  for (const YamlReader& reader : yaml_readers()) {
    INFO(reader.what);
    const std::string text = read_bytes(reader.source);
    const std::string path =
        dir.file(reader.file_name == "plant.yaml" ? "plant_copy.yaml" : reader.file_name);
    // Every cut, at a stride that still lands inside keys, values, lists and comments.
    for (std::size_t cut = 0; cut < text.size(); cut += 11) {
      const std::string truncated = text.substr(0, cut);
      write_bytes(path, truncated);
      std::string error;
      INFO("cut at byte " << cut);
      if (!reader.load(path, error)) check_names_file(error, path, count_lines(truncated));
    }
    for (int trial = 0; trial < 100; ++trial) {
      std::string damaged = text;
      for (int k = 0; k < 3; ++k)
        damaged[std::uniform_int_distribution<std::size_t>(0, damaged.size() - 1)(rng)] =
            static_cast<char>(rng());
      write_bytes(path, damaged);
      std::string error;
      INFO("damage trial " << trial);
      if (!reader.load(path, error)) check_names_file(error, path, count_lines(damaged));
    }
  }
}

TEST_CASE("the motion-capture reader reports corrupted and truncated rows by line and goes on",
          "[corrupted]") {
  // Every row of three bodies for 10 frames, then corruptions of single rows.
  std::string log = "t,body,x,y,z,qw,qx,qy,qz\n";
  for (int k = 0; k < 10; ++k) {
    const std::string t = std::to_string(0.005 * k);
    log += t + ",vehicle1,0,0,1,1,0,0,0\n";
    log += t + ",vehicle2,2,0,1.3,1,0,0,0\n";
    log += t + ",pole,0.3,0,1.8,0.98877,0,0.14944,0\n";
  }
  const auto replay = [](const std::string& text, std::string& diagnostics) {
    std::istringstream in(text);
    std::ostringstream out, diag;
    gs::estimation::ReplayOptions options;
    options.catch_height_m = 1.3;
    const gs::estimation::ReplaySummary summary = gs::estimation::replay_mocap_log(in, out, diag, options);
    diagnostics = diag.str();
    return summary;
  };

  SECTION("a corrupted row is reported with its line; the others are replayed") {
    const std::vector<std::pair<std::string, std::string>> corruptions = {
        {"0.015,pole,0.3,0,1.8,0.98877,0", "expected 9 fields"},
        {"0.015,pole,0.3,0,1.8x,0.98877,0,0.14944,0", "not a number"},
        {"0.015,pole,0.3,0,nan,0.98877,0,0.14944,0", "not finite"},
        {"0.015,cat,0.3,0,1.8,0.98877,0,0.14944,0", "unknown body"},
        {"0.015,pole,0.3,0,1.8,1.9,0,0.14944,0", "quaternion"},
        {"0.015,pole,0.3,0,1.8,0.98\0"
         "877,0,0.14944,0"s,
         "not a number"},
    };
    for (const auto& [row, expected] : corruptions) {
      INFO(row);
      // Line 11 is the pole row of frame 3 (the header is line 1).
      std::string text = log;
      std::size_t at = 0;
      for (int l = 1; l < 11; ++l) at = text.find('\n', at) + 1;
      text.replace(at, text.find('\n', at) - at, row);
      std::string diagnostics;
      const gs::estimation::ReplaySummary summary = replay(text, diagnostics);
      CHECK(summary.ok);
      CHECK(summary.malformed == 1);
      CHECK(summary.rows == 30);
      CHECK_THAT(diagnostics, Catch::StartsWith("line 11: ") && Catch::Contains(expected));
    }
  }

  SECTION("a log cut anywhere: at most its last row is reported, by its line") {
    for (std::size_t cut = 0; cut <= log.size(); cut += 7) {
      const std::string truncated = log.substr(0, cut);
      INFO("cut at byte " << cut);
      std::string diagnostics;
      const gs::estimation::ReplaySummary summary = replay(truncated, diagnostics);
      CHECK(summary.malformed <= 1);
      if (summary.malformed == 1) {
        CHECK_THAT(diagnostics, Catch::StartsWith("line " + std::to_string(summary.lines) + ": "));
      }
      if (!summary.ok) CHECK_FALSE(summary.fatal_error.empty());
    }
  }

  SECTION("random damage never throws; every problem names a line of the input") {
    std::mt19937 rng(7);
    for (int trial = 0; trial < 100; ++trial) {
      std::string damaged = log;
      for (int k = 0; k < 4; ++k)
        damaged[std::uniform_int_distribution<std::size_t>(0, damaged.size() - 1)(rng)] =
            static_cast<char>(rng());
      std::string diagnostics;
      gs::estimation::ReplaySummary summary;
      REQUIRE_NOTHROW(summary = replay(damaged, diagnostics));
      std::istringstream lines(diagnostics);
      std::string message;
      while (std::getline(lines, message)) {
        INFO(message);
        std::smatch m;
        if (!std::regex_search(message, m, std::regex("^line ([0-9]+): "))) continue;
        CHECK(std::stoul(m[1]) <= summary.lines);
      }
    }
  }
}

namespace {

using gs::adaptation::AdaptationStore;
using gs::adaptation::StoreError;

gs::adaptation::AdaptationSettings store_settings() {
  gs::adaptation::AdaptationSettings s;
  s.nominal_catch_height_m = 1.40;
  s.nominal_waiting_xy_m = {0.70, 0.05};
  s.window = 3;
  s.target_energy_J = gs::model::upright_energy_J(gs::model::PoleParams{});
  return s;
}

// The throws 1..n exactly as recorded (adaptation_test::make_record).
void check_history_is_prefix(const AdaptationStore& store, std::int64_t max_n) {
  const std::vector<gs::adaptation::StoredThrow> history = store.history();
  CHECK(static_cast<std::int64_t>(history.size()) <= max_n);
  for (std::size_t i = 0; i < history.size(); ++i) {
    CHECK(history[i].id == static_cast<std::int64_t>(i + 1));
    CHECK(adaptation_test::same_record(history[i].record, adaptation_test::make_record(history[i].id)));
  }
  CHECK(store.check_consistency().ok);
}

}  // namespace

// The store's contract (adaptation_store.hpp): a commit is on the disk when record() returns,
// and a crash leaves each transaction whole or absent. In write-ahead-log mode the commits since
// the last checkpoint live in the -wal file, so a crash in the middle of a write leaves a torn
// tail there: SQLite's frame checksums stop recovery at the last whole commit. What the store
// cannot promise is to survive a log damaged before its last commit (a disk that loses synced
// data): then it must still open on a whole prefix of the history, never a partial throw.
TEST_CASE("a torn or truncated write-ahead log: every whole commit kept, never a partial throw",
          "[corrupted]") {
  ScratchDir dir("corrupted-store-wal");
  const std::string live = dir.file("live.sqlite");
  constexpr std::int64_t kThrows = 6;
  AdaptationStore writer = AdaptationStore::open_or_create(live, store_settings());
  for (std::int64_t id = 1; id <= kThrows; ++id) writer.record(adaptation_test::make_record(id));
  // What a kill -9 now leaves: the database file and its log, the writer never closed.
  const std::string db = read_bytes(live);
  const std::string wal = read_bytes(live + "-wal");
  REQUIRE(wal.size() > 32);

  // As the mission opens its store after a crash: open_or_create, which also completes a creation
  // the crash interrupted (a log cut inside the creation leaves an empty database).
  const auto open_copy = [&](const std::string& name, const std::string& wal_bytes) {
    const std::string path = dir.file(name);
    write_bytes(path, db);
    write_bytes(path + "-wal", wal_bytes);
    return AdaptationStore::open_or_create(path, store_settings());
  };

  SECTION("garbage after the last commit (a write torn by the crash) loses nothing") {
    std::mt19937 rng(3);
    for (std::size_t tail : {1u, 24u, 100u, 4096u, 4120u, 10000u}) {
      INFO("tail of " << tail << " bytes");
      std::string torn = wal;
      for (std::size_t i = 0; i < tail; ++i) torn += static_cast<char>(rng());
      const AdaptationStore store = open_copy("torn-" + std::to_string(tail) + ".sqlite", torn);
      CHECK(store.throw_count() == kThrows);
      check_history_is_prefix(store, kThrows);
    }
  }

  SECTION("a log cut anywhere opens on a whole prefix of the history") {
    std::int64_t previous = 0;
    std::set<std::int64_t> seen;
    // Cuts at a stride prime to the frame size (24 + page size), so they fall all over the
    // frames, and the whole log last.
    for (std::size_t cut = 0;; cut = std::min(cut + 1021, wal.size())) {
      INFO("log cut at byte " << cut << " of " << wal.size());
      const AdaptationStore store = open_copy("cut-" + std::to_string(cut) + ".sqlite", wal.substr(0, cut));
      check_history_is_prefix(store, kThrows);
      // A longer log never holds fewer throws.
      CHECK(store.throw_count() >= previous);
      previous = store.throw_count();
      seen.insert(previous);
      if (cut == wal.size()) break;
    }
    CHECK(previous == kThrows);
    CHECK(seen.size() > 2);  // the cuts fell inside the history, not only before or after it
  }

  SECTION("a damaged copy leaves the original whole") {
    std::string damaged = wal;
    for (std::size_t i = 40; i < damaged.size(); i += 97) damaged[i] = static_cast<char>(~damaged[i]);
    try {
      const AdaptationStore store = open_copy("damaged.sqlite", damaged);
      check_history_is_prefix(store, kThrows);
    } catch (const StoreError& e) {
      CHECK_THAT(e.what(), Catch::Contains("damaged.sqlite"));
    }
    CHECK(writer.throw_count() == kThrows);
    check_history_is_prefix(writer, kThrows);
  }
}

TEST_CASE("a truncated store file is refused with its name and left as it was, never read short",
          "[corrupted]") {
  ScratchDir dir("corrupted-store-file");
  const std::string path = dir.file("store.sqlite");
  constexpr std::int64_t kThrows = 40;
  {
    AdaptationStore store = AdaptationStore::open_or_create(path, store_settings());
    for (std::int64_t id = 1; id <= kThrows; ++id) store.record(adaptation_test::make_record(id));
  }  // closed: the log is checkpointed into the file
  const std::string whole = read_bytes(path);
  REQUIRE(whole.size() >= 4 * 4096);

  const std::string copy = dir.file("copy.sqlite");
  for (std::size_t cut = 0; cut < whole.size(); cut += 1024) {
    INFO("file cut at byte " << cut << " of " << whole.size());
    const std::string truncated = whole.substr(0, cut);
    std::filesystem::remove(copy + "-wal");
    std::filesystem::remove(copy + "-shm");
    write_bytes(copy, truncated);
    try {
      const AdaptationStore store = AdaptationStore::open_existing(copy);
      // Only a cut that removed nothing but unused pages may open: then every throw is there.
      CHECK(store.throw_count() == kThrows);
      check_history_is_prefix(store, kThrows);
    } catch (const StoreError& e) {
      CHECK_THAT(e.what(), Catch::Contains(copy));
      CHECK(read_bytes(copy) == truncated);  // nothing modified
    }
  }
}
