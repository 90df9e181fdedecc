#include "hil/trials/campaign.hpp"

#include <cstdio>
#include <optional>
#include <stdexcept>

#include "hil/plant/randomisation.hpp"
#include "hil/trials/trial_config.hpp"
#include "hil/trials/worker_pool.hpp"

namespace hil::trials {
namespace {

CampaignAttempt fly(const CampaignConfig& config, const WarmUp& warm, int attempt) {
  CampaignAttempt a;
  a.seed = attempt_seed(config.seed, attempt);
  SeriesConfig series = attempt_config(config, warm, attempt);
  a.plant = series.plant;
  SeriesRunner runner(series);
  a.result = runner.run({campaign_attempt_plan()}).front();
  a.result.throw_number = attempt;
  return a;
}

}  // namespace

AttemptPlan campaign_attempt_plan() {
  AttemptPlan plan;
  plan.stronger_throws = true;
  return plan;
}

SeriesConfig attempt_config(const CampaignConfig& config, const WarmUp& warm, int attempt) {
  SeriesConfig series = trial_config(config.plant, attempt_seed(config.seed, attempt), PlantDraw::drawn);
  series.ground_station.learnt = warm.learnt;
  series.ground_station.fig5_throw = warm.fig5_throw;
  return series;
}

WarmUp warm_up(const PlantConfig& plant, std::uint64_t seed) {
  SeriesRunner runner(trial_config(plant, seed, PlantDraw::as_given));
  runner.run({AttemptPlan{false}});
  return {runner.ground_station().learnt(), runner.ground_station().fig5_throw()};
}

Schema<CampaignAttempt> campaign_throws_columns(const PlantConfig& plant) {
  Schema<CampaignAttempt> out;
  const auto result = [](const CampaignAttempt& a) -> const AttemptResult& { return a.result; };
  for (const Field<AttemptResult>& f :
       columns(attempt_schema(), {"throw", "outcome", "flight_s", "catch_height_m", "catch_x_m", "catch_y_m",
                                  "travel_m", "energy_error_J", "abort_reason", "vehicle_crashed",
                                  "planned_height_m", "optimal_height_m", "thrower", "innovation_switches"}))
    out.push_back(column_of<CampaignAttempt>(f, result));
  out.push_back(field("seed", &CampaignAttempt::seed));
  const std::vector<DrawnParameter> drawn = drawn_parameters(plant);
  for (std::size_t k = 0; k < drawn.size(); ++k) {
    out.push_back(column<CampaignAttempt>(std::string(drawn[k].key), [k](const CampaignAttempt& a) {
      char text[64];
      std::snprintf(text, sizeof text, "%.6g", drawn_parameters(a.plant)[k].value);
      return std::string(text);
    }));
  }
  return out;
}

AttemptRange shard_attempts(int attempts, CampaignShard shard) {
  if (attempts < 1 || shard.count < 1 || shard.index < 1 || shard.index > shard.count) return {};
  const auto edge = [&](int k) {
    return static_cast<int>(static_cast<long long>(attempts) * k / shard.count);
  };
  return {edge(shard.index - 1) + 1, edge(shard.index)};
}

std::optional<CampaignShard> parse_shard(const std::string& text) {
  const std::size_t slash = text.find('/');
  if (slash == std::string::npos) return std::nullopt;
  const auto number = [](const std::string& digits) -> std::optional<int> {
    if (digits.empty() || digits.size() > 6 || digits.find_first_not_of("0123456789") != std::string::npos)
      return std::nullopt;
    return std::stoi(digits);
  };
  const std::optional<int> k = number(text.substr(0, slash));
  const std::optional<int> n = number(text.substr(slash + 1));
  if (!k || !n || *k < 1 || *k > *n || *n > 100000) return std::nullopt;
  return CampaignShard{*k, *n};
}

std::vector<CampaignAttempt> run_campaign(
    const CampaignConfig& config,
    const std::function<void(const std::vector<const CampaignAttempt*>&)>& progress) {
  if (config.attempts < 1 || config.jobs < 1)
    throw std::runtime_error("a campaign needs attempts and jobs >= 1");
  if (config.shard.count < 1 || config.shard.index < 1 || config.shard.index > config.shard.count)
    throw std::runtime_error("a shard is K of N with 1 <= K <= N");
  const AttemptRange range = shard_attempts(config.attempts, config.shard);
  const int count = range.last - range.first + 1;
  if (count < 1) return {};
  const WarmUp warm = warm_up(config.plant, config.seed);

  // The plants are drawn here too (a draw is cheap and deterministic): the workers report only
  // the referee's results.
  std::vector<CampaignAttempt> attempts(static_cast<std::size_t>(count));
  for (int i = range.first; i <= range.last; ++i) {
    CampaignAttempt& a = attempts[static_cast<std::size_t>(i - range.first)];
    a.seed = attempt_seed(config.seed, i);
    a.plant = trial_config(config.plant, a.seed, PlantDraw::drawn).plant;
    a.result.throw_number = i;
  }
  std::vector<const CampaignAttempt*> done;
  run_on_workers(
      count, config.jobs, [&](int i) { return encode_result(fly(config, warm, i).result); },
      [&](int i, const std::string& report) {
        AttemptResult r;
        if (!decode_result(report, r))
          throw std::runtime_error("a worker reported an unreadable result: '" + report + "'");
        r.throw_number = i;
        CampaignAttempt& a = attempts[static_cast<std::size_t>(i - range.first)];
        a.result = r;
        done.push_back(&a);
        if (progress) progress(done);
      },
      "attempt", range.first);
  return attempts;
}

}  // namespace hil::trials
