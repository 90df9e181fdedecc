// The Arm CMSDK APB UART as QEMU models it on mps2-an386: five of them, UART0 at 0x40004000
// (QEMU's first -serial), UART1..3 at 0x40005000..0x40007000, UART4 at 0x40009000; UART n's
// receive interrupt is NVIC line 2n (n < 3). Polled; the receive interrupt can be latched for
// a WFI to wake on (the caller sets up the NVIC). QEMU's model holds one received byte and
// takes the next from its character device only after that one is read, so nothing is lost
// however slowly the image reads; a byte written goes to the character device at once (TXFULL
// stays set only while the host side is not reading).
#pragma once

#include <cstdint>

namespace mps2 {

class CmsdkUart {
 public:
  static constexpr std::uintptr_t kUart0 = 0x40004000u;

  explicit constexpr CmsdkUart(std::uintptr_t base) : base_(base) {}

  // Transmitter and receiver on, the receive interrupt enabled when `rx_interrupt` (the
  // NVIC line is the caller's), the others off, the fastest divider the block allows (the
  // model ignores the rate; a divider below 16 is a guest error to it).
  void enable(bool rx_interrupt = false) const;
  // Clears the latched receive interrupt.
  void clear_rx_interrupt() const;
  // Takes the received byte if there is one.
  bool read(std::uint8_t& byte) const;
  bool readable() const;
  // Waits while the transmit buffer is full, then writes the byte.
  void write(std::uint8_t byte) const;
  void write(const std::uint8_t* bytes, std::uint32_t count) const;

 private:
  struct Regs {
    volatile std::uint32_t data;
    volatile std::uint32_t state;  // bit 0 TX full, bit 1 RX full, bits 2-3 TX/RX overrun (write 1 clears)
    volatile std::uint32_t ctrl;   // bit 0 TX enable, bit 1 RX enable, bits 2-5 interrupt enables
    volatile std::uint32_t intstatus;
    volatile std::uint32_t bauddiv;
  };
  Regs& regs() const { return *reinterpret_cast<Regs*>(base_); }

  std::uintptr_t base_;
};

}  // namespace mps2
