#include "uart.hpp"

#include "pins.hpp"

namespace stm32f405 {

using namespace stm32f4;

void Uart::init(std::uintptr_t base, unsigned irq, const Pin& tx, const Pin& rx, std::uint32_t kernel_hz,
                std::uint32_t baud, std::uint8_t priority) {
  base_ = base;
  irq_ = irq;
  if (base_ == kUsart1Base) rcc().APB2ENR |= rcc_bits::apb2_usart1;
  else rcc().APB1ENR |= rcc_bits::apb1_usart3;
  (void)rcc().APB1ENR;
  configure_pin(tx, gpio_mode_af);
  configure_pin(rx, gpio_mode_af, Pull::up);  // an unconnected line idles high, not in noise
  Usart& u = regs();
  u.CR1 = 0;
  u.BRR = (kernel_hz + baud / 2u) / baud;  // 16x oversampling: mantissa.fraction is kernel / baud
  u.CR2 = 0;
  u.CR3 = 0;
  u.CR1 = usart_bits::cr1_ue | usart_bits::cr1_te | usart_bits::cr1_re | usart_bits::cr1_rxneie;
  nvic_enable(irq_, priority);
}

bool Uart::send(const std::uint8_t* data, std::size_t n) {
  // One producer (the main loop), so the free space only grows while this runs.
  std::size_t queued = 0;
  for (; queued < n; ++queued)
    if (!tx_.push(data[queued])) break;
  if (queued < n) stats_.tx_dropped += static_cast<std::uint32_t>(n - queued);
  const std::uint32_t saved = irq_save();
  regs().CR1 |= usart_bits::cr1_txeie;
  irq_restore(saved);
  return queued == n;
}

void Uart::move_out() {
  Usart& u = regs();
  // At most a few bytes: the hardware takes one while TXE is set (QEMU's takes any number).
  for (int i = 0; i < 16 && (u.SR & usart_bits::sr_txe) != 0u; ++i) {
    std::uint8_t b;
    if (!tx_.pop(b)) {
      u.CR1 &= ~usart_bits::cr1_txeie;
      return;
    }
    u.DR = b;
    ++stats_.tx_bytes;
  }
}

void Uart::kick() {
  const std::uint32_t saved = irq_save();
  move_out();
  irq_restore(saved);
}

void Uart::on_interrupt() {
  Usart& u = regs();
  const std::uint32_t sr = u.SR;
  if ((sr & (usart_bits::sr_rxne | usart_bits::sr_ore)) != 0u) {
    const auto b = static_cast<std::uint8_t>(u.DR);  // reading DR after SR also clears ORE
    if ((sr & usart_bits::sr_ore) != 0u) ++stats_.rx_overruns;
    if (rx_.push(b)) ++stats_.rx_bytes;
    else ++stats_.rx_dropped;
  }
  if ((u.CR1 & usart_bits::cr1_txeie) != 0u) move_out();
}

}  // namespace stm32f405
