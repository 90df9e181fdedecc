// `groundstation history` and `groundstation adaptation`, run in-process: the exit codes (0 done,
// 1 missing or damaged store, 2 bad arguments with the usage on stderr), the table, the CSV with
// its header row and exact numbers, and the confirmed reset.
#include "groundstation/adaptation/adaptation_cli.hpp"

#include <catch2/catch.hpp>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <string>
#include <vector>

#include "adaptation_test_support.hpp"
#include "groundstation/adaptation/adaptation_store.hpp"
#include "groundstation/adaptation/history_report.hpp"
#include "groundstation/model/impact.hpp"

namespace {

using namespace gs::adaptation;
using adaptation_test::make_identification;
using adaptation_test::make_record;
using adaptation_test::ScratchDir;

struct Run {
  int code = -1;
  std::string out;
  std::string err;
};

Run run(int (*command)(int, const char* const*, std::ostream&, std::ostream&),
        std::initializer_list<std::string> args) {
  std::vector<std::string> storage(args);
  std::vector<const char*> argv;
  for (const std::string& a : storage) argv.push_back(a.c_str());
  std::ostringstream out, err;
  Run r;
  r.code = command(static_cast<int>(argv.size()), argv.data(), out, err);
  r.out = out.str();
  r.err = err.str();
  return r;
}

Run history(std::initializer_list<std::string> args) { return run(run_history_command, args); }
Run adaptation_cmd(std::initializer_list<std::string> args) { return run(run_adaptation_command, args); }

AdaptationSettings settings() { return adaptation_test::nominal_settings(); }

// RFC 4180 records: fields split on commas outside quotes, records on line breaks outside quotes.
std::vector<std::vector<std::string>> parse_csv(const std::string& text) {
  std::vector<std::vector<std::string>> rows(1);
  std::string field;
  bool quoted = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (quoted) {
      if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
        field += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        field += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      rows.back().push_back(field);
      field.clear();
    } else if (c == '\n') {
      rows.back().push_back(field);
      field.clear();
      rows.emplace_back();
    } else {
      field += c;
    }
  }
  if (rows.back().empty() && field.empty()) rows.pop_back();
  return rows;
}

int count_lines(const std::string& text) {
  int n = 0;
  for (const char c : text) n += (c == '\n');
  return n;
}

}  // namespace

TEST_CASE("history and adaptation reject bad arguments with the usage and exit 2") {
  for (const Run& r : {history({"history"}), history({"history", "--db"}),
                       history({"history", "--db", "x.sqlite", "--last", "0"}),
                       history({"history", "--db", "x.sqlite", "--last", "-3"}),
                       history({"history", "--db", "x.sqlite", "--last", "3x"}),
                       history({"history", "--db", "x.sqlite", "--color"}), adaptation_cmd({"adaptation"}),
                       adaptation_cmd({"adaptation", "--db", "x.sqlite", "--yes"}),
                       adaptation_cmd({"adaptation", "--db", "x.sqlite", "--frobnicate"})}) {
    INFO(r.err);
    CHECK(r.code == 2);
    CHECK(r.out.empty());
    CHECK_THAT(r.err, Catch::Contains("usage: groundstation"));
  }
  const Run help = history({"history", "--help"});
  CHECK(help.code == 0);
  CHECK_THAT(help.out, Catch::Contains("--last N"));
  CHECK(adaptation_cmd({"adaptation", "-h"}).code == 0);
}

TEST_CASE("a missing or damaged store is a clear message and exit 1") {
  ScratchDir dir("adaptation-cli-bad");
  const std::string missing = dir.file("missing.sqlite");
  const Run a = history({"history", "--db", missing});
  CHECK(a.code == 1);
  CHECK_THAT(a.err, Catch::Contains("does not exist") && Catch::Contains(missing));
  CHECK(adaptation_cmd({"adaptation", "--db", missing}).code == 1);

  const std::string garbage = dir.file("garbage.sqlite");
  std::ofstream(garbage) << std::string(2000, '#') << "\n";
  const Run b = adaptation_cmd({"adaptation", "--db", garbage});
  CHECK(b.code == 1);
  CHECK_THAT(b.err, Catch::Contains("not an adaptation store"));
  CHECK(count_lines(b.err) == 1);  // a message, not a usage text or a trace
}

TEST_CASE("history prints a table, the last N, or CSV with a header row and exact numbers") {
  ScratchDir dir("adaptation-cli-history");
  const std::string path = dir.file("store.sqlite");
  {
    AdaptationStore store = AdaptationStore::open_or_create(path, settings());
    const Run empty = history({"history", "--db", path});
    CHECK(empty.code == 0);
    CHECK_THAT(empty.out, Catch::Contains("no throws recorded"));
    for (int id = 1; id <= 10; ++id) store.record(make_record(id));
  }
  const Run table = history({"history", "--db", path});
  INFO(table.err);
  REQUIRE(table.code == 0);
  CHECK(count_lines(table.out) == 1 + 10 + 1);  // header, a line per throw, the count
  CHECK_THAT(table.out, Catch::StartsWith("id "));
  CHECK_THAT(table.out, Catch::Contains("aborted_out_of_reach") && Catch::Contains("10 of 10 throws"));
  // The note with a line break stays on its throw's line.
  CHECK_THAT(table.out, Catch::Contains("a comma and a line break"));

  const Run last = history({"history", "--db", path, "--last", "3"});
  REQUIRE(last.code == 0);
  CHECK(count_lines(last.out) == 1 + 3 + 1);
  CHECK_THAT(last.out, Catch::Contains("3 of 10 throws"));

  const Run csv = history({"history", "--db", path, "--csv"});
  REQUIRE(csv.code == 0);
  const auto rows = parse_csv(csv.out);
  REQUIRE(rows.size() == 11);
  const auto header = parse_csv(history_csv_header() + "\n").front();
  CHECK(rows.front() == header);
  auto column = [&](const char* name) {
    return static_cast<std::size_t>(std::find(header.begin(), header.end(), name) - header.begin());
  };
  for (std::size_t i = 1; i < rows.size(); ++i) {
    const ThrowRecord r = make_record(static_cast<std::int64_t>(i));
    INFO("row " << i);
    REQUIRE(rows[i].size() == header.size());
    CHECK(rows[i][column("id")] == std::to_string(i));
    CHECK(rows[i][column("outcome")] == to_string(r.outcome));
    CHECK(rows[i][column("thrower")] == (r.thrower ? std::to_string(r.thrower->node()) : ""));
    CHECK(std::strtod(rows[i][column("time_s")].c_str(), nullptr) == r.time_s);
    CHECK(std::strtod(rows[i][column("launch_alpha_dot_radps")].c_str(), nullptr) ==
          r.launch.alpha_dot_radps);
    CHECK(rows[i][column("note")] == r.note);
    if (r.optimal) {
      CHECK(std::strtod(rows[i][column("optimal_height_m")].c_str(), nullptr) == r.optimal->height_m);
    } else {
      CHECK(rows[i][column("optimal_height_m")].empty());
    }
    const auto bias = offset_bias_sample(r);
    CHECK(rows[i][column("bias_sample_x_m")].empty() == !bias);
  }
  const Run csv_last = history({"history", "--db", path, "--csv", "--last", "2"});
  const auto last_rows = parse_csv(csv_last.out);
  REQUIRE(last_rows.size() == 3);
  CHECK(last_rows[1][0] == "9");
}

TEST_CASE("adaptation prints the adapted values and resets only with --yes") {
  ScratchDir dir("adaptation-cli-values");
  const std::string path = dir.file("store.sqlite");
  AdaptationState state;
  {
    AdaptationStore store = AdaptationStore::open_or_create(path, settings());
    for (int id = 1; id <= 14; ++id) store.record(make_record(id));
    state = store.adaptation().state;
  }
  const Run shown = adaptation_cmd({"adaptation", "--db", path});
  INFO(shown.err);
  REQUIRE(shown.code == 0);
  char height[64];
  std::snprintf(height, sizeof height, "catching height:     %.4f m   (%lld throws", state.catch_height_m,
                static_cast<long long>(state.catch_point_samples));
  CHECK_THAT(shown.out, Catch::Contains(height));
  char bias[64];
  std::snprintf(bias, sizeof bias, "(%+.4f, %+.4f) m   (%lld catches", state.offset_bias_m.x(),
                state.offset_bias_m.y(), static_cast<long long>(state.bias_samples));
  CHECK_THAT(shown.out, Catch::Contains(bias));
  CHECK_THAT(shown.out, Catch::Contains("consistent with the history: yes"));

  const Run unconfirmed = adaptation_cmd({"adaptation", "--db", path, "--reset"});
  CHECK(unconfirmed.code == 2);
  CHECK_THAT(unconfirmed.err, Catch::Contains("--yes"));
  CHECK(AdaptationStore::open_existing(path).adaptation().state == state);

  const Run confirmed = adaptation_cmd({"adaptation", "--db", path, "--reset", "--yes"});
  CHECK(confirmed.code == 0);
  CHECK_THAT(confirmed.out, Catch::Contains("reset") && Catch::Contains("no throws yet"));
  const AdaptationStore store = AdaptationStore::open_existing(path);
  CHECK(store.adaptation().state == initial_adaptation(settings()));
  CHECK(store.throw_count() == 14);
}

namespace {

// The lines of `text` that start with `prefix`.
std::vector<std::string> lines_starting(const std::string& text, const std::string& prefix) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind(prefix, 0) == 0) out.push_back(line);
  }
  return out;
}

std::string lag_ms(double s) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.1f", 1e3 * s);
  return buffer;
}

}  // namespace

TEST_CASE("history lists the motor identifications after the throws, or alone with --identifications") {
  ScratchDir dir("adaptation-cli-identifications");
  const std::string path = dir.file("store.sqlite");
  {
    AdaptationStore store = AdaptationStore::open_or_create(path, settings());
    for (int id = 1; id <= 4; ++id) store.record(make_record(id));
    const Run none = history({"history", "--db", path, "--identifications"});
    CHECK(none.code == 0);
    CHECK_THAT(none.out, Catch::Contains("no motor identifications recorded"));
    // A store without identifications prints its throws as before.
    CHECK(count_lines(history({"history", "--db", path}).out) == 1 + 4 + 1);
    for (int id = 1; id <= 9; ++id) store.record_identification(make_identification(id));
  }
  const Run both = history({"history", "--db", path});
  INFO(both.err);
  REQUIRE(both.code == 0);
  // The throws' table and count, a blank line, the identifications' table and count.
  CHECK(count_lines(both.out) == (1 + 4 + 1) + 1 + (1 + 9 + 1));
  CHECK_THAT(both.out, Catch::Contains("4 of 4 throws\n\nid    vehicle time_s"));
  CHECK_THAT(both.out, Catch::EndsWith("9 of 9 motor identifications\n"));
  for (int id = 1; id <= 9; ++id) {
    const IdentificationRecord r = make_identification(id);
    const std::vector<std::string> line = lines_starting(both.out, std::to_string(id) + "  ");
    REQUIRE(line.size() == (id <= 4 ? 2u : 1u));  // ids 1-4 also start a throw's line
    const std::string& l = line.back();
    INFO(l);
    CHECK_THAT(l, Catch::Contains(std::string(outcome_name(r.result))));
    if (const auto& m = r.result.identified) {
      CHECK_THAT(l,
                 Catch::Contains(lag_ms(m->time_constant_s) + " ") &&
                     Catch::Contains(lag_ms(m->time_constant_low_s) + "-" + lag_ms(m->time_constant_high_s)));
    } else {
      CHECK_THAT(l, Catch::Contains(" -  "));
    }
  }

  const Run last = history({"history", "--db", path, "--last", "2"});
  CHECK_THAT(last.out, Catch::Contains("2 of 4 throws") && Catch::Contains("2 of 9 motor identifications"));

  const Run alone = history({"history", "--db", path, "--identifications"});
  REQUIRE(alone.code == 0);
  CHECK_THAT(alone.out, Catch::StartsWith("id    vehicle time_s"));
  CHECK(count_lines(alone.out) == 1 + 9 + 1);

  // --csv stays the throws' (one header row); with --identifications, every stored column exactly.
  CHECK(parse_csv(history({"history", "--db", path, "--csv"}).out).size() == 1 + 4);
  const Run csv = history({"history", "--db", path, "--identifications", "--csv"});
  REQUIRE(csv.code == 0);
  const auto rows = parse_csv(csv.out);
  REQUIRE(rows.size() == 1 + 9);
  const auto header = parse_csv(identification_csv_header() + "\n").front();
  CHECK(rows.front() == header);
  for (std::size_t i = 1; i < rows.size(); ++i) {
    const IdentificationRecord r = make_identification(static_cast<std::int64_t>(i));
    INFO("row " << i);
    REQUIRE(rows[i].size() == header.size());
    CHECK(rows[i][0] == std::to_string(i));
    CHECK(rows[i][1] == std::to_string(r.vehicle.node()));
    CHECK(std::strtod(rows[i][2].c_str(), nullptr) == r.time_s);
    CHECK(rows[i][3] == outcome_name(r.result));
    if (r.result.identified) {
      CHECK(std::strtod(rows[i][4].c_str(), nullptr) == r.result.identified->time_constant_s);
      CHECK(std::strtod(rows[i][6].c_str(), nullptr) == r.result.identified->time_constant_high_s);
      CHECK(rows[i][10] == std::to_string(r.result.identified->samples));
    } else {
      CHECK(rows[i][4].empty());
      CHECK(rows[i][10].empty());
    }
    CHECK(rows[i][11].empty() == !r.thrust_gain);
    if (r.thrust_gain) CHECK(std::strtod(rows[i][11].c_str(), nullptr) == *r.thrust_gain);
  }
}

TEST_CASE("adaptation prints each vehicle's last identification and a latest refusal") {
  ScratchDir dir("adaptation-cli-identification-summary");
  const std::string path = dir.file("store.sqlite");
  AdaptationStore store = AdaptationStore::open_or_create(path, settings());
  const Run none = adaptation_cmd({"adaptation", "--db", path});
  REQUIRE(none.code == 0);
  CHECK_THAT(none.out, Catch::Contains("motor identifications: none"));

  for (int id = 1; id <= 9; ++id) store.record_identification(make_identification(id));
  const Run shown = adaptation_cmd({"adaptation", "--db", path});
  INFO(shown.out);
  REQUIRE(shown.code == 0);
  CHECK_THAT(shown.out, Catch::Contains("consistent with the history: yes"));
  // Vehicle 1: identification 7 in force, 9 refused.
  const IdentificationRecord seven = make_identification(7);
  const auto& m = *seven.result.identified;
  char expected[256];
  std::snprintf(expected, sizeof expected,
                "    vehicle 1: lag %.1f ms (95 %%: %.1f-%.1f ms), inertia %.3f, round trip %.1f ms, "
                "thrust gain %.4f; identification 7 at t %.3f s (5 identifications)\n",
                1e3 * m.time_constant_s, 1e3 * m.time_constant_low_s, 1e3 * m.time_constant_high_s,
                m.inertia_gain, 1e3 * m.round_trip_s, *seven.thrust_gain, seven.time_s);
  CHECK_THAT(shown.out, Catch::Contains(expected));
  const IdentificationRecord nine = make_identification(9);
  std::snprintf(expected, sizeof expected,
                "      latest refused: %s, identification 9 at t %.3f s; the lag above is kept\n",
                std::string(outcome_name(nine.result)).c_str(), nine.time_s);
  CHECK_THAT(shown.out, Catch::Contains(expected));
  // Vehicle 2: identification 8 in force and latest (measured without a thrust gain: "-").
  const std::vector<std::string> two = lines_starting(shown.out, "    vehicle 2: ");
  REQUIRE(two.size() == 1);
  CHECK_THAT(two.front(), Catch::Contains("thrust gain -; identification 8 at t") &&
                              Catch::EndsWith("(4 identifications)"));
  CHECK(lines_starting(shown.out, "      latest refused").size() == 1);

  // A vehicle only ever refused: the design lag stays.
  IdentificationRecord refused = make_identification(3);
  refused.vehicle = pa::VehicleId(3);
  store.record_identification(refused);
  const Run third = adaptation_cmd({"adaptation", "--db", path});
  CHECK_THAT(third.out,
             Catch::Contains("    vehicle 3: no accepted identification (the firmware's design lag "
                             "stays) (1 identification)\n      latest refused: "));
}
