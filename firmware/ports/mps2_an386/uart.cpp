#include "uart.hpp"

namespace mps2 {
namespace {

constexpr std::uint32_t kStateTxFull = 1u << 0;
constexpr std::uint32_t kStateRxFull = 1u << 1;
constexpr std::uint32_t kStateOverruns = (1u << 2) | (1u << 3);
constexpr std::uint32_t kCtrlTxEnable = 1u << 0;
constexpr std::uint32_t kCtrlRxEnable = 1u << 1;
constexpr std::uint32_t kCtrlRxInterrupt = 1u << 3;
constexpr std::uint32_t kIntRx = 1u << 1;
constexpr std::uint32_t kBaudDivMin = 16;

}  // namespace

void CmsdkUart::enable(bool rx_interrupt) const {
  regs().ctrl = 0;
  regs().bauddiv = kBaudDivMin;
  regs().state = kStateOverruns;
  regs().intstatus = ~0u;  // INTCLEAR on write
  regs().ctrl = kCtrlTxEnable | kCtrlRxEnable | (rx_interrupt ? kCtrlRxInterrupt : 0u);
}

void CmsdkUart::clear_rx_interrupt() const { regs().intstatus = kIntRx; }

bool CmsdkUart::readable() const { return (regs().state & kStateRxFull) != 0u; }

bool CmsdkUart::read(std::uint8_t& byte) const {
  if ((regs().state & kStateRxFull) == 0u) return false;
  byte = static_cast<std::uint8_t>(regs().data);
  return true;
}

void CmsdkUart::write(std::uint8_t byte) const {
  while ((regs().state & kStateTxFull) != 0u) {
  }
  regs().data = byte;
}

void CmsdkUart::write(const std::uint8_t* bytes, std::uint32_t count) const {
  for (std::uint32_t i = 0; i < count; ++i) write(bytes[i]);
}

}  // namespace mps2
