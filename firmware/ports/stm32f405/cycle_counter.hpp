// The Cortex-M4 DWT cycle counter: the tick's cost in real CPU cycles, and the clock for the
// start-up timeouts (it runs from reset, before any peripheral clock is set up).
#pragma once

#include <cstdint>

#include "registers.hpp"

namespace stm32f405 {

class CycleCounter {
 public:
  static void start() {
    stm32f4::demcr() |= stm32f4::demcr_trcena;
    stm32f4::dwt_lar() = 0xC5ACCE55u;
    stm32f4::dwt().CYCCNT = 0;
    stm32f4::dwt().CTRL |= stm32f4::dwt_ctrl_cyccntena;
  }
  // Wraps every 2^32 cycles (25.6 s at 168 MHz); differences are wrap-safe.
  static std::uint32_t now() { return stm32f4::dwt().CYCCNT; }
};

// Waits until (reg & mask) == value; false after `timeout_cycles`. Each pass takes well over
// four cycles (two peripheral reads and a dozen instructions), so the pass count bounds the
// wait too: a cycle counter that does not run (an emulator without a DWT) cannot hang it.
inline bool wait_for(stm32f4::Reg& reg, std::uint32_t mask, std::uint32_t value,
                     std::uint32_t timeout_cycles) {
  const std::uint32_t start = CycleCounter::now();
  for (std::uint32_t pass = 0; (reg & mask) != value; ++pass) {
    if (CycleCounter::now() - start > timeout_cycles || pass > timeout_cycles / 4u) return false;
  }
  return true;
}

}  // namespace stm32f405
