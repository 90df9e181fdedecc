// Interrupt-driven USART with a lock-free ring each way: the radio link (USART1) and the text
// console (USART3) of the flight image. send() queues without waiting (a full ring drops and
// counts); the TXE interrupt moves bytes out, and kick() does the same from the main loop so
// that output also flows where the TXE interrupt is not modelled (QEMU 7.2's USART). Received
// bytes go into the receive ring from the RXNE interrupt. No heap, nothing blocks.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fw/drivers/omnibus_f4.hpp"
#include "registers.hpp"
#include "spsc_ring.hpp"

namespace stm32f405 {

struct UartStats {
  std::uint32_t tx_bytes = 0;
  std::uint32_t tx_dropped = 0;  // the transmit ring was full
  std::uint32_t rx_bytes = 0;
  std::uint32_t rx_dropped = 0;   // the receive ring was full
  std::uint32_t rx_overruns = 0;  // a byte arrived before the interrupt read the last one
};

class Uart {
 public:
  using Pin = fw::drivers::omnibus_f4::Pin;
  // `base`, `irq`: the USART's registers and interrupt line; `kernel_hz`: its bus clock (APB2
  // for USART1, APB1 for USART3). Nothing else may be called before. (Set here rather than in
  // a constructor, so the rings are zero-initialised .bss instead of .data copied from flash.)
  void init(std::uintptr_t base, unsigned irq, const Pin& tx, const Pin& rx, std::uint32_t kernel_hz,
            std::uint32_t baud, std::uint8_t priority);

  // Queues `n` bytes, all or none; false (and counted) when they do not fit.
  bool send(const std::uint8_t* data, std::size_t n);
  bool receive(std::uint8_t& byte) { return rx_.pop(byte); }
  bool rx_pending() const { return !rx_.empty(); }
  void kick();  // moves what the transmitter takes now (main loop)
  void on_interrupt();
  const UartStats& stats() const { return stats_; }

 private:
  stm32f4::Usart& regs() const { return stm32f4::at<stm32f4::Usart>(base_); }
  void move_out();  // with interrupts masked or from the interrupt itself: the ring's one consumer at a time

  std::uintptr_t base_ = 0;
  unsigned irq_ = 0;
  SpscRing<std::uint8_t, 512> tx_;
  SpscRing<std::uint8_t, 256> rx_;
  UartStats stats_{};
};

}  // namespace stm32f405
