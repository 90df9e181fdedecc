// The vehicle's link identity on the STM32F405 (docs/security.md): its key, in a flash slot of
// its own that `make flash KEY=FILE` fills (scripts/flash.sh), and this boot's session nonce from
// the chip's hardware RNG. An image as built (by CI too) has an erased slot: no key, and the
// vehicle accepts no ground frame until one is flashed with it.
#pragma once

#include "fw/config.hpp"

namespace stm32f405 {

// Fills link.key from the slot and link.session_nonce from the RNG. False when the RNG gave no
// number in time (or failed its self-test): then the key is cleared, because a boot without a
// fresh nonce could repeat an earlier session, whose frames an attacker may have recorded.
bool load_link_identity(fw::LinkConfig& link, std::uint32_t sysclk_hz);

}  // namespace stm32f405
