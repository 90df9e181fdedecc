// Per-run draws of the plant's uncertain parameters: the pole's drag coefficients, each motor's
// thrust gain and time constant, the vehicles' drag, the contact friction, the motion-capture
// latency, every noise level, the pole's mass and length (a few percent off the model the
// ground station flies with) and the radios' frame loss. The spreads are in PlantConfig::randomisation; the draws come
// from their own random stream, so a seed gives the same world on every run and platform, and
// different seeds give different worlds.
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

#include "hil/plant/plant_config.hpp"

namespace hil {

// `nominal` with the uncertain parameters drawn around their nominal values: a value x with
// spread fraction f becomes x * U(1 - f, 1 + f); the latency is drawn from
// U(latency_min_s, latency_max_s), the radio loss from U(radio_loss_min, radio_loss_max).
// Everything else is copied unchanged. With random_profile 1, the arena envelope instead
// (EnvelopeConfig): each vehicle's thrust scale, mass, inertia, motor time constant and
// battery's starting charge, the pole's drag, length, mass and centre of mass, the motion
// capture's latency, jitter and noise and the radios' loss over its ranges; the motor mismatch,
// the vehicles' drag, the friction and the IMU's noise with the spreads above.
PlantConfig randomised(const PlantConfig& nominal, std::uint64_t seed);

// The parameters randomised() draws, by their configuration keys (plant_config.hpp), in the
// order it draws them (the envelope's grouped by what they describe): what a campaign records
// beside each attempt's outcome.
struct DrawnParameter {
  std::string_view key;
  double value = 0.0;
};
std::vector<DrawnParameter> drawn_parameters(const PlantConfig& config);

}  // namespace hil
