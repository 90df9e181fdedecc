// What the mps2-an386 image adds to the shared Cortex-M runtime (cortex_m/runtime.hpp): its
// vector table, a fault handler that reports over semihosting, and the exit path that hands
// main()'s status to QEMU.
#include <cstdint>

#include "console.hpp"
#include "cortex_m/runtime.hpp"
#include "instruction_counter.hpp"
#include "semihosting.hpp"

extern "C" {
void SysTick_Handler();
}

// QEMU fetches the vector table from address 0, where VTOR already points at reset.
extern "C" void pa_board_reset_init() {}

extern "C" void pa_board_exit(int status) { mps2::semihosting::exit(static_cast<std::uint32_t>(status)); }

// An unexpected exception ends the run as a failure that names it, rather than hanging QEMU.
extern "C" void Default_Handler() {
  std::uint32_t ipsr;
  asm volatile("mrs %0, ipsr" : "=r"(ipsr));
  mps2::ConsoleLine().text("selftest: fail exception ").u32(ipsr & 0x1FFu).emit();
  mps2::semihosting::exit(1);
}

extern "C" void SysTick_Handler() { mps2::InstructionCounter::on_wrap(); }

namespace {

constexpr unsigned kIrqLines = 32;  // QEMU's AN385/AN386 interrupt controller has 32 lines

// No external interrupt is enabled by this image; SysTick widens the instruction counter.
constexpr cortex_m::VectorTable<kIrqLines> make_vector_table() {
  auto t = cortex_m::default_vector_table<kIrqLines>();
  t.exception(cortex_m::exception::sys_tick) = SysTick_Handler;
  return t;
}

}  // namespace

extern "C" __attribute__((section(".isr_vector"), used)) constinit const cortex_m::VectorTable<kIrqLines>
    g_vector_table = make_vector_table();
