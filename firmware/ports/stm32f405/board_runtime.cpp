// What both STM32F405 images add to the shared Cortex-M runtime (cortex_m/runtime.hpp): VTOR
// set at reset, and a fault handler that halts silently. Each image's vector table is in its
// own startup file (startup.cpp for HIL, flight_startup.cpp for flight).
#include <cstdint>

#include "cortex_m/runtime.hpp"
#include "registers.hpp"

extern "C" {
// The exception number of the fault that stopped the firmware, for a debugger to read.
volatile std::uint32_t g_fault_exception = 0;
}

// The boot pins alias flash at 0; say explicitly where the table is.
extern "C" void pa_board_reset_init() { stm32f4::scb().VTOR = 0x08000000u; }

// main() never returns; if it did, the firmware stops as on a fault (exception number 0).
extern "C" void pa_board_exit(int) { Default_Handler(); }

// A fault stops the firmware here with interrupts off (nothing more goes out on the bus or the
// motor outputs, so the plant or the ground sees the vehicle fall silent); a debugger finds the
// cause in g_fault_exception.
extern "C" void Default_Handler() {
  std::uint32_t ipsr;
  asm volatile("mrs %0, ipsr" : "=r"(ipsr));
  asm volatile("cpsid i" ::: "memory");
  g_fault_exception = ipsr & 0x1FFu;
  for (;;) asm volatile("wfi");
}
