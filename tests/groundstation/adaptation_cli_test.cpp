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

AdaptationSettings settings() {
  AdaptationSettings s;
  s.nominal_catch_height_m = 1.40;
  s.nominal_waiting_xy_m = {0.70, 0.0};
  s.target_energy_J = gs::model::upright_energy_J(gs::model::PoleParams{});
  return s;
}

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
