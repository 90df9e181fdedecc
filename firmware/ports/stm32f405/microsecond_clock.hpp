// A free-running 32-bit microsecond clock on a 32-bit timer of APB1 (TIM2 in the HIL image,
// TIM5 in the flight image, whose TIM2 drives motors): it wraps every 2^32 us (71.6 min)
// exactly like the firmware core's std::uint32_t microsecond times, so differences are
// wrap-safe with pa::elapsed_us.
#pragma once

#include <cstdint>

#include "registers.hpp"

namespace stm32f405 {

template <std::uintptr_t TimerBase, std::uint32_t Apb1EnableBit>
class MicrosecondClockOn {
 public:
  // `timer_clock_hz` is the timer's kernel clock (ClockReport::apb1_timer_hz), a whole number of MHz.
  static void start(std::uint32_t timer_clock_hz) {
    stm32f4::rcc().APB1ENR |= Apb1EnableBit;
    (void)stm32f4::rcc().APB1ENR;
    stm32f4::Tim& t = timer();
    t.CR1 = 0;
    t.PSC = timer_clock_hz / 1000000u - 1u;
    t.ARR = 0xFFFFFFFFu;
    t.CNT = 0;
    t.EGR = 1u;  // UG: load the prescaler now rather than at the first overflow
    t.SR = 0;
    t.CR1 = 1u;  // CEN
  }
  static std::uint32_t now_us() { return timer().CNT; }

 private:
  static stm32f4::Tim& timer() { return stm32f4::at<stm32f4::Tim>(TimerBase); }
};

using MicrosecondClock = MicrosecondClockOn<stm32f4::kTim2Base, stm32f4::rcc_bits::apb1_tim2>;
using FlightMicrosecondClock = MicrosecondClockOn<stm32f4::kTim5Base, stm32f4::rcc_bits::apb1_tim5>;

}  // namespace stm32f405
