#include "hil/trials/campaign_files.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <utility>

#include "hil/trials/trial_config.hpp"

namespace hil::trials {
namespace {

constexpr const char* kManifest = "shard.txt";
constexpr const char* kAttempts = "attempts.tsv";
constexpr const char* kPlant = "plant.yaml";
constexpr const char* kManifestTitle = "hil campaign shard";
constexpr int kShardFormat = 1;

// Wilson's score interval for k successes in n trials at 95%: unlike the normal approximation
// it stays inside [0, 1] and is honest near 100%, where a campaign's rate lies.
std::pair<double, double> wilson95(int k, int n) {
  const double z = 1.959964;
  const double p = static_cast<double>(k) / n;
  const double d = 1.0 + z * z / n;
  const double centre = (p + z * z / (2.0 * n)) / d;
  const double half = z * std::sqrt(p * (1.0 - p) / n + z * z / (4.0 * n * n)) / d;
  return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

std::string record_fields() {
  std::string out;
  for (const Field<AttemptResult>& f : attempt_schema()) out += (out.empty() ? "" : ",") + f.name;
  return out;
}

// Writes `text` to DIR/name through a temporary file renamed into place.
bool write_file(const std::string& dir, const std::string& name, const std::string& text,
                std::string& error) {
  const std::filesystem::path path = std::filesystem::path(dir) / name;
  const std::filesystem::path temporary = path.string() + ".tmp";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out << text;
    out.close();
    if (!out) {
      error = "cannot write '" + temporary.string() + "'";
      return false;
    }
  }
  std::error_code ec;
  std::filesystem::rename(temporary, path, ec);
  if (ec) {
    error = "cannot write '" + path.string() + "': " + ec.message();
    return false;
  }
  return true;
}

bool read_file(const std::filesystem::path& path, std::string& text) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::ostringstream buffer;
  buffer << in.rdbuf();
  text = buffer.str();
  return !in.bad();
}

// A non-negative decimal that fits `limit`, or nullopt.
std::optional<std::uint64_t> decimal(const std::string& text, std::uint64_t limit) {
  if (text.empty() || text.size() > 20 || text.find_first_not_of("0123456789") != std::string::npos)
    return std::nullopt;
  try {
    const unsigned long long v = std::stoull(text);
    if (v > limit) return std::nullopt;
    return v;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

std::string shard_name(CampaignShard s) { return std::to_string(s.index) + "/" + std::to_string(s.count); }

}  // namespace

std::string campaign_summary(const std::vector<AttemptResult>& results) {
  std::map<std::string, int> failures;
  int caught = 0, crashed = 0;
  long long innovation_switches = 0;
  for (const AttemptResult& r : results) {
    innovation_switches += r.innovation_switches;
    if (r.outcome == gs::adaptation::ThrowOutcome::caught) {
      ++caught;
    } else {
      const std::string outcome(gs::adaptation::to_string(r.outcome));
      ++failures[r.abort_reason.empty() ? outcome : outcome + " (" + r.abort_reason + ")"];
    }
    if (r.vehicle_crashed) ++crashed;
  }
  const int n = static_cast<int>(results.size());
  if (n == 0) return "campaign: no attempts\n";
  const auto [lo, hi] = wilson95(caught, n);
  char line[256];
  std::snprintf(line, sizeof line,
                "campaign: %d of %d attempts caught and balanced again for 3 s: %.1f%% (95%% interval "
                "%.1f-%.1f%%)\n",
                caught, n, 100.0 * caught / n, 100.0 * lo, 100.0 * hi);
  std::string out = line;
  for (const auto& [cause, count] : failures) {
    std::snprintf(line, sizeof line, "  %4d  ", count);
    out += line + cause + "\n";
  }
  out += "  vehicles crashed in " + std::to_string(crashed) + " attempts\n";
  std::snprintf(line, sizeof line, "  pole mode switches on the innovations: %lld (%.2f an attempt)\n",
                innovation_switches, static_cast<double>(innovation_switches) / n);
  return out + line;
}

std::string plant_hash(const PlantConfig& plant) {
  std::uint64_t h = 14695981039346656037ull;
  for (const char c : format_plant_config(plant)) {
    h ^= static_cast<unsigned char>(c);
    h *= 1099511628211ull;
  }
  char text[24];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(h));
  return text;
}

bool write_campaign(const std::string& dir, const CampaignConfig& config,
                    const std::vector<AttemptResult>& results, std::string& error) {
  // The header's keys depend on the plant's randomisation profile, not on a draw's values.
  const Schema<CampaignAttempt> columns =
      campaign_throws_columns(trial_config(config.plant, config.seed, PlantDraw::drawn).plant);
  std::ostringstream csv;
  csv << csv_header(columns) << "\n";
  for (const AttemptResult& r : results) {
    CampaignAttempt a;
    a.result = r;
    a.seed = attempt_seed(config.seed, r.throw_number);
    a.plant = trial_config(config.plant, a.seed, PlantDraw::drawn).plant;
    csv << csv_row(columns, a) << "\n";
  }
  return write_file(dir, "throws.csv", csv.str(), error) &&
         write_file(dir, "summary.txt", campaign_summary(results), error);
}

bool write_shard(const std::string& dir, const CampaignConfig& config,
                 const std::vector<AttemptResult>& results, std::string& error) {
  const AttemptRange range = shard_attempts(config.attempts, config.shard);
  // A shard flown again into its folder: no manifest until its new records are in place.
  std::error_code ec;
  std::filesystem::remove(std::filesystem::path(dir) / kManifest, ec);
  std::string records;
  for (const AttemptResult& r : results) records += encode_result(r) + "\n";
  std::ostringstream manifest;
  manifest << kManifestTitle << "\n"
           << "format " << kShardFormat << "\n"
           << "seed " << config.seed << "\n"
           << "attempts " << config.attempts << "\n"
           << "plant " << plant_hash(config.plant) << "\n"
           << "fields " << record_fields() << "\n"
           << "shard " << shard_name(config.shard) << "\n"
           << "first " << range.first << "\n"
           << "last " << range.last << "\n";
  return write_file(dir, kPlant, format_plant_config(config.plant), error) &&
         write_file(dir, kAttempts, records, error) && write_file(dir, kManifest, manifest.str(), error);
}

bool read_shard(const std::string& dir, ShardFolder& shard, std::string& error) {
  const std::filesystem::path folder(dir);
  shard = ShardFolder{};
  shard.dir = dir;
  std::string text;
  if (!std::filesystem::is_directory(folder)) {
    error = "'" + dir + "' is not a folder";
    return false;
  }
  if (!read_file(folder / kManifest, text)) {
    error = "'" + dir + "' holds no finished shard (no " + kManifest + ": the shard did not finish)";
    return false;
  }
  const std::string manifest_path = (folder / kManifest).string();
  std::map<std::string, std::string> entries;
  std::istringstream lines(text);
  std::string line;
  if (!std::getline(lines, line) || line != kManifestTitle) {
    error =
        "'" + manifest_path + "' is not a shard manifest (its first line is not '" + kManifestTitle + "')";
    return false;
  }
  while (std::getline(lines, line)) {
    const std::size_t space = line.find(' ');
    if (space == std::string::npos) {
      error = "'" + manifest_path + "': a line is not 'key value': '" + line + "'";
      return false;
    }
    entries[line.substr(0, space)] = line.substr(space + 1);
  }
  const auto entry = [&](const char* key) -> std::optional<std::string> {
    const auto it = entries.find(key);
    if (it == entries.end()) {
      error = "'" + manifest_path + "' has no '" + key + "'";
      return std::nullopt;
    }
    return it->second;
  };
  const auto number = [&](const char* key, std::uint64_t limit) -> std::optional<std::uint64_t> {
    const std::optional<std::string> value = entry(key);
    if (!value) return std::nullopt;
    const std::optional<std::uint64_t> n = decimal(*value, limit);
    if (!n) error = "'" + manifest_path + "': '" + key + "' is not a number: '" + *value + "'";
    return n;
  };
  const std::optional<std::uint64_t> format = number("format", 1000);
  if (!format) return false;
  if (*format != kShardFormat) {
    error = "'" + manifest_path + "' is of shard format " + std::to_string(*format) + "; this hil reads " +
            std::to_string(kShardFormat);
    return false;
  }
  const std::optional<std::uint64_t> seed = number("seed", UINT64_MAX);
  const std::optional<std::uint64_t> attempts = seed ? number("attempts", 1000000) : std::nullopt;
  const std::optional<std::uint64_t> first = attempts ? number("first", 1000001) : std::nullopt;
  const std::optional<std::uint64_t> last = first ? number("last", 1000000) : std::nullopt;
  const std::optional<std::string> hash = last ? entry("plant") : std::nullopt;
  const std::optional<std::string> fields = hash ? entry("fields") : std::nullopt;
  const std::optional<std::string> shard_text = fields ? entry("shard") : std::nullopt;
  if (!shard_text) return false;
  if (*attempts < 1) {
    error = "'" + manifest_path + "': a campaign of no attempts";
    return false;
  }
  const std::optional<CampaignShard> split = parse_shard(*shard_text);
  if (!split) {
    error = "'" + manifest_path + "': 'shard' is not K/N: '" + *shard_text + "'";
    return false;
  }
  if (*fields != record_fields()) {
    error = "'" + manifest_path + "' records the fields '" + *fields + "'; this hil's are '" +
            record_fields() + "' (a shard of another version)";
    return false;
  }
  shard.config.seed = *seed;
  shard.config.attempts = static_cast<int>(*attempts);
  shard.config.shard = *split;
  shard.plant_hash = *hash;
  shard.range = shard_attempts(shard.config.attempts, *split);
  if (shard.range.first != static_cast<int>(*first) || shard.range.last != static_cast<int>(*last)) {
    error = "'" + manifest_path + "': attempts " + std::to_string(*first) + "-" + std::to_string(*last) +
            " are not shard " + *shard_text + "'s of " + std::to_string(*attempts);
    return false;
  }

  const std::string plant_path = (folder / kPlant).string();
  if (!read_file(plant_path, text)) {
    error = "cannot read '" + plant_path + "'";
    return false;
  }
  std::string plant_error;
  if (!parse_plant_config(text, plant_path, shard.config.plant, plant_error)) {
    error = plant_error;
    return false;
  }
  // Canonical, as write_shard() wrote it: a file edited since (even to the same values) is not the shard's.
  if (format_plant_config(shard.config.plant) != text) {
    error = "'" + plant_path + "' is not the canonical plant file its shard wrote (edited since?)";
    return false;
  }
  if (plant_hash(shard.config.plant) != shard.plant_hash) {
    error = "'" + plant_path + "' is not the plant of its manifest (hash " + plant_hash(shard.config.plant) +
            ", the manifest says " + shard.plant_hash + ")";
    return false;
  }

  const std::string records_path = (folder / kAttempts).string();
  if (!read_file(records_path, text)) {
    error = "cannot read '" + records_path + "'";
    return false;
  }
  std::istringstream records(text);
  int expected = shard.range.first;
  int line_number = 0;
  while (std::getline(records, line)) {
    ++line_number;
    AttemptResult r;
    if (!decode_result(line, r) || r.throw_number != expected) {
      error = "'" + records_path + "' line " + std::to_string(line_number) +
              " is not the record of attempt " + std::to_string(expected);
      return false;
    }
    shard.results.push_back(r);
    ++expected;
  }
  if (expected != shard.range.last + 1) {
    error = "'" + records_path + "' holds " + std::to_string(expected - shard.range.first) +
            " records; the manifest says " + std::to_string(shard.range.last - shard.range.first + 1);
    return false;
  }
  return true;
}

bool merge_shards(const std::vector<ShardFolder>& shards, MergedCampaign& merged, std::string& error) {
  merged = MergedCampaign{};
  if (shards.empty()) {
    error = "no shards to merge";
    return false;
  }
  const ShardFolder& first = shards.front();
  for (const ShardFolder& s : shards) {
    std::string differs;
    if (s.config.seed != first.config.seed) {
      differs = "seed " + std::to_string(s.config.seed) + ", not " + std::to_string(first.config.seed);
    } else if (s.config.attempts != first.config.attempts) {
      differs = std::to_string(s.config.attempts) + " attempts, not " + std::to_string(first.config.attempts);
    } else if (s.plant_hash != first.plant_hash) {
      differs = "plant " + s.plant_hash + ", not " + first.plant_hash;
    }
    if (!differs.empty()) {
      error = "'" + s.dir + "' is a shard of another campaign than '" + first.dir + "' (" + differs +
              "): merge only the shards of one campaign";
      return false;
    }
  }
  merged.config = first.config;
  merged.config.shard = CampaignShard{};
  const auto n = static_cast<std::size_t>(first.config.attempts);
  std::vector<const AttemptResult*> found(n, nullptr);
  std::vector<const std::string*> found_in(n, nullptr);
  for (const ShardFolder& s : shards) {
    for (const AttemptResult& r : s.results) {
      const auto i = static_cast<std::size_t>(r.throw_number - 1);
      if (found[i] != nullptr && encode_result(*found[i]) != encode_result(r)) {
        error = "attempt " + std::to_string(r.throw_number) + " differs between '" + *found_in[i] +
                "' and '" + s.dir + "'";
        return false;
      }
      found[i] = &r;
      found_in[i] = &s.dir;
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (found[i] == nullptr) {
      merged.missing.push_back(static_cast<int>(i + 1));
    } else {
      merged.results.push_back(*found[i]);
    }
  }
  return true;
}

std::string describe_missing(const std::vector<int>& missing, int attempts, int n_ways) {
  std::string out;
  for (std::size_t i = 0; i < missing.size();) {
    std::size_t j = i;
    while (j + 1 < missing.size() && missing[j + 1] == missing[j] + 1) ++j;
    // A run that crosses shards' edges is named once per shard.
    int from = missing[i];
    while (from <= missing[j]) {
      int to = missing[j];
      std::string shard;
      if (n_ways > 0) {
        for (int k = 1; k <= n_ways; ++k) {
          const AttemptRange r = shard_attempts(attempts, CampaignShard{k, n_ways});
          if (from >= r.first && from <= r.last) {
            to = std::min(to, r.last);
            shard = " (shard " + shard_name(CampaignShard{k, n_ways}) + ")";
            break;
          }
        }
      }
      if (!out.empty()) out += ", ";
      out += std::to_string(from) + (to > from ? "-" + std::to_string(to) : "") + shard;
      from = to + 1;
    }
    i = j + 1;
  }
  return out;
}

}  // namespace hil::trials
