// How the arena's radios are configured and which frames they carry, for every rig that puts
// radios between the ground bus and the vehicle buses (plant_exchange.hpp, and through it the
// in-process arena, hil/sil/arena.hpp).
#pragma once

#include <array>
#include <cstdint>

#include "hil/plant/plant_config.hpp"
#include "hil/radio/radio_bridge.hpp"
#include "pa/protocol.hpp"
#include "pa/vehicle_id.hpp"

namespace hil::run {

// `radio` losing frames as `plant` says (radio_loss_probability, radio_outage_s): how every trial
// configures its radios from its plant (hil/trials/trial_config.hpp).
RadioConfig with_plant_losses(RadioConfig radio, const PlantConfig& plant);

// A vehicle's radio: `radio` with its seed derived from the arena's seed and the vehicle's node
// (RadioConfig::seed is not used), so the two radios draw distinct, reproducible losses and jitter.
RadioConfig arena_radio_config(RadioConfig radio, std::uint64_t arena_seed, pa::VehicleId vehicle);

// Which act vehicles' radios carry a frame put on the ground bus, indexed by pa::act_slot(): the
// vehicle its identifier addresses, both for a broadcast (node 15), none for any other node.
std::array<bool, 2> radios_carrying(const pa::proto::Frame& frame);

// splitmix64: nearby arena seeds and the two nodes give unrelated seeds.
std::uint64_t mix_seed(std::uint64_t x);

}  // namespace hil::run
