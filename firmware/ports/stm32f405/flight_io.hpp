// The flight image's shared pieces between its main loop and its interrupt handlers: the two
// USARTs and the 1 ms housekeeping beat (SysTick).
#pragma once

#include <cstdint>

#include "uart.hpp"

namespace stm32f405::flight {

Uart& link();     // USART1: the ground link (pa/serial_frame.hpp frames)
Uart& console();  // USART3: status lines
void on_millisecond();
std::uint32_t milliseconds();

}  // namespace stm32f405::flight
