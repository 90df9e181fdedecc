#include "groundstation/adaptation/adaptation_cli.hpp"

#include <cstdint>
#include <exception>
#include <optional>
#include <string>

#include "groundstation/adaptation/adaptation_store.hpp"
#include "groundstation/adaptation/history_report.hpp"
#include "pa/command_line.hpp"

namespace gs::adaptation {
namespace {

int store_error(std::ostream& err, const char* command, const std::string& message) {
  err << "groundstation " << command << ": " << message << "\n";
  return 1;
}

void write_identifications(std::ostream& out, const AdaptationStore& store,
                           std::optional<std::int64_t> last_n, bool csv) {
  const std::vector<StoredIdentification> rows = store.identifications(last_n);
  if (csv) {
    write_identification_csv(out, rows);
  } else if (rows.empty()) {
    out << "no motor identifications recorded in " << store.path() << "\n";
  } else {
    write_identification_table(out, rows);
    out << rows.size() << " of " << store.identification_count() << " motor identifications\n";
  }
}

int history(int argc, const char* const* argv, std::ostream& out, std::ostream& err) {
  constexpr const char* kName = "history";
  std::string db;
  std::optional<std::uint64_t> last;
  bool csv = false;
  bool identifications_only = false;
  CLI::App app("", "groundstation history");
  pa::cli::describe(
      app, "usage: groundstation history --db FILE [--last N] [--csv] [--identifications]",
      "Prints the throws recorded in the adaptation store FILE, oldest first: launch state, the\n"
      "catching height used, the predicted and actual catch points, the optimal catch (42)\n"
      "evaluated after the throw, the catcher's bias sample, |E - E*| after the impact (41), the\n"
      "outcome and the note; then, if there are any, the motor identifications of the take-offs\n"
      "(vehicle, outcome or refusal, lag and its 95 % interval, inertia, round trip, thrust gain).\n"
      "--csv writes the throws only (one header row); --identifications the identifications only.",
      "Exit 0 done, 1 the store is missing or damaged, 2 bad arguments.");
  app.add_option("--db", db, "the adaptation store (a SQLite file written by the mission)")
      ->type_name("FILE")
      ->required()
      ->check(pa::cli::non_empty("wants a file name"));
  app.add_option("--last", last, "only the last N throws (N >= 1)")
      ->type_name("N")
      ->check(pa::cli::count(1, INT64_MAX, "wants a whole number >= 1"));
  app.add_flag("--csv", csv, "CSV with a header row and every stored column, instead of the table");
  app.add_flag("--identifications", identifications_only,
               "the motor identifications only (with --last: the last N of them)");
  if (const std::optional<int> code = pa::cli::parse(app, argc, argv, out, err)) return *code;
  try {
    const AdaptationStore store = AdaptationStore::open_existing(db);
    const std::optional<std::int64_t> last_n =
        last ? std::optional<std::int64_t>(static_cast<std::int64_t>(*last)) : std::nullopt;
    if (identifications_only) {
      write_identifications(out, store, last_n, csv);
      return 0;
    }
    const std::vector<StoredThrow> throws = store.history(last_n);
    if (csv) {
      write_history_csv(out, throws);
    } else if (throws.empty()) {
      out << "no throws recorded in " << db << "\n";
    } else {
      write_history_table(out, throws);
      out << throws.size() << " of " << store.throw_count() << " throws\n";
    }
    if (!csv && store.identification_count() > 0) {
      out << "\n";
      write_identifications(out, store, last_n, false);
    }
  } catch (const std::exception& e) {
    return store_error(err, kName, e.what());
  }
  return 0;
}

int adaptation(int argc, const char* const* argv, std::ostream& out, std::ostream& err) {
  constexpr const char* kName = "adaptation";
  std::string db;
  bool reset = false;
  bool yes = false;
  CLI::App app("", "groundstation adaptation");
  pa::cli::describe(
      app, "usage: groundstation adaptation --db FILE [--reset --yes]",
      "Prints the adapted catching height, waiting position and catcher offset bias (paper,\n"
      "Section VI) held in the adaptation store FILE, how many throws they rest on, and whether\n"
      "they agree with the recorded history; then per vehicle its last accepted motor\n"
      "identification (lag and 95 % interval, thrust gain, when) and its latest if refused.",
      "Exit 0 done, 1 the store is missing or damaged, 2 bad arguments.");
  app.add_option("--db", db, "the adaptation store")
      ->type_name("FILE")
      ->required()
      ->check(pa::cli::non_empty("wants a file name"));
  CLI::Option* reset_flag =
      app.add_flag("--reset", reset,
                   "set the adapted values back to the nominal ones (the history is kept; the\n"
                   "values then rest on later throws only); needs --yes to confirm");
  app.add_flag("--yes", yes, "confirms --reset")->needs(reset_flag);
  if (const std::optional<int> code = pa::cli::parse(app, argc, argv, out, err)) return *code;
  try {
    AdaptationStore store = AdaptationStore::open_existing(db);
    if (reset) {
      const AdaptationSnapshot before = store.adaptation();
      if (!yes) {
        err << "groundstation adaptation: --reset discards the adapted values resting on "
            << before.state.catch_point_samples << " throws and " << before.state.bias_samples
            << " catches (the history is kept); add --yes to confirm\n\n"
            << app.help();
        return 2;
      }
      store.reset();
      out << "reset: the adapted values are the nominal ones again; they will rest on throws "
          << before.throw_count + 1 << " onwards\n";
    }
    write_adaptation_summary(out, db, store.settings(), store.adaptation(), store.check_consistency());
    write_identification_summary(out, store.identifications_by_vehicle());
  } catch (const std::exception& e) {
    return store_error(err, kName, e.what());
  }
  return 0;
}

}  // namespace

int run_history_command(int argc, const char* const* argv, std::ostream& out, std::ostream& err) {
  try {
    return history(argc, argv, out, err);
  } catch (const std::exception& e) {
    err << "groundstation history: " << e.what() << "\n";
    return 1;
  }
}

int run_adaptation_command(int argc, const char* const* argv, std::ostream& out, std::ostream& err) {
  try {
    return adaptation(argc, argv, out, err);
  } catch (const std::exception& e) {
    err << "groundstation adaptation: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace gs::adaptation
