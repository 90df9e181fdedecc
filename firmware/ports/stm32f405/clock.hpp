// System clock set-up: HSE 8 MHz -> PLL -> 168 MHz SYSCLK, AHB 168 MHz, APB1 42 MHz, APB2
// 84 MHz, flash at 5 wait states. Every wait has a timeout, so a board without a working
// crystal still starts: it falls back to the PLL fed by the internal 16 MHz HSI (same
// frequencies, but only about 1 % accurate, which is outside CAN's tolerance at 1 Mbit/s),
// and if the PLL does not lock either, to the bare HSI. The report says which happened.
#pragma once

#include <cstdint>

namespace stm32f405 {

enum class ClockSource : std::uint8_t { hse_pll = 0, hsi_pll = 1, hsi = 2 };

struct ClockReport {
  ClockSource source = ClockSource::hsi;
  bool hse_failed = false;  // the crystal did not start within its timeout
  bool pll_failed = false;  // the PLL did not lock or could not be selected
  std::uint32_t sysclk_hz = 16000000;
  std::uint32_t apb1_hz = 16000000;
  std::uint32_t apb2_hz = 16000000;
  std::uint32_t apb1_timer_hz = 16000000;  // TIM2..7: twice APB1 when APB1 is divided
};

// Run once at start-up, from the reset clock (HSI), with the cycle counter running.
ClockReport clock_init();

}  // namespace stm32f405
