// The configuration of a trial, made in one place for every command that flies one (`hil fly`,
// `hil campaign`, `hil cuts`, `hil run`): the plant (as given, or drawn from its ranges with the
// trial's seed, hil/plant/randomisation.hpp), both radios losing frames as that plant says
// (radio_loss_probability, radio_outage_s: with_plant_losses()), and the trial's seed for the
// plant's noise and the radios. What a command adds on top (the ground station's learnt state,
// its store, a pre-flight rest, recording, logs) is its own.
//
// One seed rule for the attempts of a trial: attempt k (1..N) of a trial seeded S is seeded
// attempt_seed(S, k), in a campaign, in the missions of `hil cuts` and in `hil fly --randomise`
// alike, so attempt k of each flies the same drawn plant.
#pragma once

#include <cstdint>

#include "hil/plant/plant_config.hpp"
#include "hil/trials/series.hpp"

namespace hil::trials {

enum class PlantDraw {
  as_given,  // the plant as configured
  drawn,     // randomised(plant, seed)
};

// The seed of attempt k (1..N) of a trial seeded with `seed`.
std::uint64_t attempt_seed(std::uint64_t seed, int attempt);

// A trial on `plant` (drawn from it with `seed` when `draw` says so), its radios losing frames as
// that plant says, its noise and radios seeded with `seed`.
SeriesConfig trial_config(const PlantConfig& plant, std::uint64_t seed, PlantDraw draw);

}  // namespace hil::trials
