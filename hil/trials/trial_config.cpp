#include "hil/trials/trial_config.hpp"

#include "hil/plant/randomisation.hpp"
#include "hil/run/radio_routing.hpp"

namespace hil::trials {

std::uint64_t attempt_seed(std::uint64_t seed, int attempt) {
  return seed * 1000003ULL + static_cast<std::uint64_t>(attempt);
}

SeriesConfig trial_config(const PlantConfig& plant, std::uint64_t seed, PlantDraw draw) {
  SeriesConfig config;
  config.plant = draw == PlantDraw::drawn ? randomised(plant, seed) : plant;
  config.arena.radio = run::with_plant_losses(config.arena.radio, config.plant);
  config.seed = seed;
  return config;
}

}  // namespace hil::trials
