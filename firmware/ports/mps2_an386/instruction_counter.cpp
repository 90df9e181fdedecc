#include "instruction_counter.hpp"

namespace mps2 {
namespace {

struct SysTickRegs {
  volatile std::uint32_t csr;  // control and status
  volatile std::uint32_t rvr;  // reload value
  volatile std::uint32_t cvr;  // current value (counts down)
  volatile std::uint32_t calib;
};
SysTickRegs& systick() { return *reinterpret_cast<SysTickRegs*>(0xE000E010u); }
volatile std::uint32_t& scb_icsr() { return *reinterpret_cast<volatile std::uint32_t*>(0xE000ED04u); }

constexpr std::uint32_t kCsrEnable = 1u << 0;
constexpr std::uint32_t kCsrTickInt = 1u << 1;
constexpr std::uint32_t kCsrClkSourceCpu = 1u << 2;
constexpr std::uint32_t kIcsrPendStSet = 1u << 26;
constexpr std::uint32_t kReload = 0x00FFFFFFu;  // the full 24-bit range
constexpr std::uint32_t kPeriod = kReload + 1u;

volatile std::uint32_t g_wraps = 0;

}  // namespace

void InstructionCounter::start() {
  systick().csr = 0;
  systick().rvr = kReload;
  systick().cvr = 0;  // any write clears the counter; it reloads on the next clock
  g_wraps = 0;
  systick().csr = kCsrEnable | kCsrTickInt | kCsrClkSourceCpu;
}

void InstructionCounter::on_wrap() { g_wraps = g_wraps + 1u; }

// Not inlined, so every reading costs the same instructions and the empty-bracket overhead
// that main() subtracts is the overhead of every reading.
__attribute__((noinline)) std::uint64_t InstructionCounter::counts() {
  for (;;) {
    const std::uint32_t wraps = g_wraps;
    const std::uint32_t value = systick().cvr;
    const bool pending = (scb_icsr() & kIcsrPendStSet) != 0u;
    if (wraps != g_wraps) continue;  // the wrap interrupt ran in between: read again
    // A wrap whose interrupt is still pending belongs to this reading only if the counter
    // was read after the reload (high value); a low value was read just before the wrap.
    const std::uint32_t periods = wraps + ((pending && value > kPeriod / 2u) ? 1u : 0u);
    return static_cast<std::uint64_t>(periods) * kPeriod + (kReload - value);
  }
}

}  // namespace mps2
