// Configures one pin of the board table (fw/drivers/omnibus_f4.hpp) on its GPIO port.
#pragma once

#include <cstdint>

#include "fw/drivers/omnibus_f4.hpp"
#include "registers.hpp"

namespace stm32f405 {

enum class Pull : std::uint32_t { none = 0, up = 1, down = 2 };

inline void configure_pin(const fw::drivers::omnibus_f4::Pin& pin, std::uint32_t mode,
                          Pull pull = Pull::none) {
  using namespace stm32f4;
  rcc().AHB1ENR |= pin.port == 'A'   ? rcc_bits::ahb1_gpioa
                   : pin.port == 'B' ? rcc_bits::ahb1_gpiob
                                     : rcc_bits::ahb1_gpioc;
  (void)rcc().AHB1ENR;
  Gpio& g = gpio(pin.port);
  const std::uint32_t n = pin.number;
  if (mode == gpio_mode_af) {
    Reg& afr = n < 8 ? g.AFRL : g.AFRH;
    const std::uint32_t shift = 4u * (n % 8u);
    afr = (afr & ~(0xFu << shift)) | (static_cast<std::uint32_t>(pin.alternate_function) << shift);
  }
  g.OTYPER &= ~(1u << n);                                        // push-pull
  g.OSPEEDR = (g.OSPEEDR & ~(3u << (2 * n))) | (2u << (2 * n));  // fast
  g.PUPDR = (g.PUPDR & ~(3u << (2 * n))) | (static_cast<std::uint32_t>(pull) << (2 * n));
  g.MODER = (g.MODER & ~(3u << (2 * n))) | (mode << (2 * n));
}

inline void write_pin(const fw::drivers::omnibus_f4::Pin& pin, bool high) {
  stm32f4::gpio(pin.port).BSRR = high ? (1u << pin.number) : (1u << (pin.number + 16u));
}

}  // namespace stm32f405
