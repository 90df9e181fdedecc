#include "hil/sil/campaign.hpp"

#include <cstdio>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "hil/plant/randomisation.hpp"
#include "hil/sil/worker_pool.hpp"

namespace hil::sil {
namespace {

CampaignAttempt fly(const CampaignConfig& config, const gs::adaptation::Learnt& learnt, int attempt) {
  CampaignAttempt a;
  a.seed = attempt_seed(config.seed, attempt);
  a.plant = randomised(config.plant, a.seed);
  SeriesConfig series;
  series.plant = a.plant;
  series.arena.radio = with_plant_losses(series.arena.radio, a.plant);
  series.seed = a.seed;
  series.ground_station.learnt = learnt;
  SeriesRunner runner(series);
  a.result = runner.run({AttemptPlan{}}).front();
  a.result.throw_number = attempt;
  return a;
}

}  // namespace

gs::adaptation::Learnt warm_up(const PlantConfig& plant, std::uint64_t seed) {
  SeriesConfig series;
  series.plant = plant;
  series.arena.radio = with_plant_losses(series.arena.radio, plant);
  series.seed = seed;
  SeriesRunner runner(series);
  runner.run({AttemptPlan{false}});
  return runner.ground_station().learnt();
}

std::uint64_t attempt_seed(std::uint64_t seed, int attempt) {
  return seed * 1000003ULL + static_cast<std::uint64_t>(attempt);
}

std::string encode_result(const AttemptResult& r) {
  char numbers[256];
  std::snprintf(numbers, sizeof numbers, "%.17g\t%.17g\t%.17g\t%.17g\t%.17g\t%.17g\t%d\t%d", r.flight_s,
                r.catch_height_m, r.catch_x_m, r.catch_y_m, r.travel_m, r.energy_error_J, r.impact ? 1 : 0,
                r.vehicle_crashed ? 1 : 0);
  return r.outcome + "\t" + numbers + "\t" + r.abort_reason;
}

bool decode_result(const std::string& line, AttemptResult& r) {
  std::vector<std::string> fields;
  std::stringstream in(line);
  std::string field;
  while (std::getline(in, field, '\t')) fields.push_back(field);
  if (line.empty() || line.back() == '\t') fields.emplace_back();
  if (fields.size() != 10) return false;
  try {
    r.outcome = fields[0];
    r.flight_s = std::stod(fields[1]);
    r.catch_height_m = std::stod(fields[2]);
    r.catch_x_m = std::stod(fields[3]);
    r.catch_y_m = std::stod(fields[4]);
    r.travel_m = std::stod(fields[5]);
    r.energy_error_J = std::stod(fields[6]);
    r.impact = fields[7] == "1";
    r.vehicle_crashed = fields[8] == "1";
    r.abort_reason = fields[9];
  } catch (const std::exception&) {
    return false;
  }
  return true;
}

std::vector<CampaignAttempt> run_campaign(
    const CampaignConfig& config,
    const std::function<void(const std::vector<const CampaignAttempt*>&)>& progress) {
  if (config.attempts < 1 || config.jobs < 1)
    throw std::runtime_error("a campaign needs attempts and jobs >= 1");
  const gs::adaptation::Learnt learnt = warm_up(config.plant, config.seed);

  // The plants are drawn here too (a draw is cheap and deterministic): the workers report only
  // the referee's results.
  std::vector<CampaignAttempt> attempts(static_cast<std::size_t>(config.attempts));
  for (int i = 1; i <= config.attempts; ++i) {
    CampaignAttempt& a = attempts[static_cast<std::size_t>(i - 1)];
    a.seed = attempt_seed(config.seed, i);
    a.plant = randomised(config.plant, a.seed);
    a.result.throw_number = i;
  }
  std::vector<const CampaignAttempt*> done;
  run_on_workers(
      config.attempts, config.jobs, [&](int i) { return encode_result(fly(config, learnt, i).result); },
      [&](int i, const std::string& report) {
        AttemptResult r;
        if (!decode_result(report, r))
          throw std::runtime_error("a worker reported an unreadable result: '" + report + "'");
        r.throw_number = i;
        CampaignAttempt& a = attempts[static_cast<std::size_t>(i - 1)];
        a.result = r;
        done.push_back(&a);
        if (progress) progress(done);
      },
      "attempt");
  return attempts;
}

}  // namespace hil::sil
