#include "groundstation/adaptation/adaptation_cli.hpp"

#include <cerrno>
#include <cstdlib>
#include <exception>
#include <optional>
#include <string>
#include <string_view>

#include "groundstation/adaptation/adaptation_store.hpp"
#include "groundstation/adaptation/history_report.hpp"

namespace gs::adaptation {
namespace {

constexpr const char* kHistoryUsage =
    "usage: groundstation history --db FILE [--last N] [--csv]\n"
    "\n"
    "Prints the throws recorded in the adaptation store FILE, oldest first: launch state, the\n"
    "catching height used, the predicted and actual catch points, the optimal catch (42)\n"
    "evaluated after the throw, the catcher's bias sample, |E - E*| after the impact (41), the\n"
    "outcome and the note.\n"
    "\n"
    "  --db FILE   the adaptation store (a SQLite file written by the mission)\n"
    "  --last N    only the last N throws (N >= 1)\n"
    "  --csv       CSV with a header row and every stored column, instead of the table\n"
    "\n"
    "Exit 0 done, 1 the store is missing or damaged, 2 bad arguments.\n";

constexpr const char* kAdaptationUsage =
    "usage: groundstation adaptation --db FILE [--reset --yes]\n"
    "\n"
    "Prints the adapted catching height, waiting position and catcher offset bias (paper,\n"
    "Section VI) held in the adaptation store FILE, how many throws they rest on, and whether\n"
    "they agree with the recorded history.\n"
    "\n"
    "  --db FILE   the adaptation store\n"
    "  --reset     set the adapted values back to the nominal ones (the history is kept; the\n"
    "              values then rest on later throws only); needs --yes to confirm\n"
    "  --yes       confirms --reset\n"
    "\n"
    "Exit 0 done, 1 the store is missing or damaged, 2 bad arguments.\n";

int usageError(std::ostream& err, const char* command, const char* usage,
               const std::string& message) {
  err << "groundstation " << command << ": " << message << "\n\n" << usage;
  return 2;
}

int storeError(std::ostream& err, const char* command, const std::string& message) {
  err << "groundstation " << command << ": " << message << "\n";
  return 1;
}

std::optional<long long> parsePositive(std::string_view text) {
  if (text.empty() || text.front() == '-' || text.front() == '+') return std::nullopt;
  const std::string s(text);
  char* end = nullptr;
  errno = 0;
  const long long value = std::strtoll(s.c_str(), &end, 10);
  if (errno != 0 || end != s.c_str() + s.size() || value < 1) return std::nullopt;
  return value;
}

int history(int argc, const char* const* argv, std::ostream& out, std::ostream& err) {
  constexpr const char* kName = "history";
  std::optional<std::string> db;
  std::optional<long long> last;
  bool csv = false;
  for (int i = 1; i < argc; ++i) {
    const std::string_view flag = argv[i];
    if (flag == "--help" || flag == "-h") {
      out << kHistoryUsage;
      return 0;
    }
    if (flag == "--csv") {
      csv = true;
      continue;
    }
    if (flag != "--db" && flag != "--last") {
      return usageError(err, kName, kHistoryUsage, "unknown argument " + std::string(flag));
    }
    if (i + 1 >= argc) {
      return usageError(err, kName, kHistoryUsage, "missing value after " + std::string(flag));
    }
    const std::string_view value = argv[++i];
    if (flag == "--db") {
      if (value.empty()) return usageError(err, kName, kHistoryUsage, "--db wants a file name");
      db = std::string(value);
    } else {
      last = parsePositive(value);
      if (!last) return usageError(err, kName, kHistoryUsage, "--last wants a whole number >= 1");
    }
  }
  if (!db) return usageError(err, kName, kHistoryUsage, "--db is required");
  try {
    const AdaptationStore store = AdaptationStore::openExisting(*db);
    const std::vector<StoredThrow> throws =
        store.history(last ? std::optional<std::int64_t>(*last) : std::nullopt);
    if (csv) {
      writeHistoryCsv(out, throws);
    } else if (throws.empty()) {
      out << "no throws recorded in " << *db << "\n";
    } else {
      writeHistoryTable(out, throws);
      out << throws.size() << " of " << store.throwCount() << " throws\n";
    }
  } catch (const std::exception& e) {
    return storeError(err, kName, e.what());
  }
  return 0;
}

int adaptation(int argc, const char* const* argv, std::ostream& out, std::ostream& err) {
  constexpr const char* kName = "adaptation";
  std::optional<std::string> db;
  bool reset = false;
  bool yes = false;
  for (int i = 1; i < argc; ++i) {
    const std::string_view flag = argv[i];
    if (flag == "--help" || flag == "-h") {
      out << kAdaptationUsage;
      return 0;
    }
    if (flag == "--reset") {
      reset = true;
    } else if (flag == "--yes") {
      yes = true;
    } else if (flag == "--db") {
      if (i + 1 >= argc) return usageError(err, kName, kAdaptationUsage, "missing value after --db");
      db = std::string(argv[++i]);
      if (db->empty()) return usageError(err, kName, kAdaptationUsage, "--db wants a file name");
    } else {
      return usageError(err, kName, kAdaptationUsage, "unknown argument " + std::string(flag));
    }
  }
  if (!db) return usageError(err, kName, kAdaptationUsage, "--db is required");
  if (yes && !reset) return usageError(err, kName, kAdaptationUsage, "--yes only confirms --reset");
  try {
    AdaptationStore store = AdaptationStore::openExisting(*db);
    if (reset) {
      const AdaptationSnapshot before = store.adaptation();
      if (!yes) {
        return usageError(err, kName, kAdaptationUsage,
                          "--reset discards the adapted values resting on " +
                              std::to_string(before.state.catch_point_samples) + " throws and " +
                              std::to_string(before.state.bias_samples) +
                              " catches (the history is kept); add --yes to confirm");
      }
      store.reset();
      out << "reset: the adapted values are the nominal ones again; they will rest on throws "
          << before.throw_count + 1 << " onwards\n";
    }
    writeAdaptationSummary(out, *db, store.settings(), store.adaptation(),
                           store.checkConsistency());
  } catch (const std::exception& e) {
    return storeError(err, kName, e.what());
  }
  return 0;
}

}  // namespace

int runHistoryCommand(int argc, const char* const* argv, std::ostream& out, std::ostream& err) {
  try {
    return history(argc, argv, out, err);
  } catch (const std::exception& e) {
    err << "groundstation history: " << e.what() << "\n";
    return 1;
  }
}

int runAdaptationCommand(int argc, const char* const* argv, std::ostream& out, std::ostream& err) {
  try {
    return adaptation(argc, argv, out, err);
  } catch (const std::exception& e) {
    err << "groundstation adaptation: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace gs::adaptation
