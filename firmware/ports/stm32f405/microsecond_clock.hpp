// A free-running 32-bit microsecond clock on TIM2 (32 bits wide, on APB1): it wraps every
// 2^32 us (71.6 min) exactly like the firmware core's std::uint32_t microsecond times, so
// differences are wrap-safe with pa::elapsed_us.
#pragma once

#include <cstdint>

#include "registers.hpp"

namespace stm32f405 {

class MicrosecondClock {
 public:
  // `timer_clock_hz` is TIM2's kernel clock (ClockReport::apb1_timer_hz), a whole number of MHz.
  static void start(std::uint32_t timer_clock_hz) {
    stm32f4::rcc().APB1ENR |= stm32f4::rcc_bits::apb1_tim2;
    (void)stm32f4::rcc().APB1ENR;
    stm32f4::Tim& t = stm32f4::tim2();
    t.CR1 = 0;
    t.PSC = timer_clock_hz / 1000000u - 1u;
    t.ARR = 0xFFFFFFFFu;
    t.CNT = 0;
    t.EGR = 1u;  // UG: load the prescaler now rather than at the first overflow
    t.SR = 0;
    t.CR1 = 1u;  // CEN
  }
  static std::uint32_t now_us() { return stm32f4::tim2().CNT; }
};

}  // namespace stm32f405
