// Reset, vector table and the bare C++ runtime of the STM32F405 image: no C library start
// files, no heap. Reset enables the FPU, copies .data, zeroes .bss, paints the stack (for its
// high-water mark), runs the static constructors and calls main(). The vector table has the STM32F405's 82 interrupt lines
// (RM0090 table 61); the CAN1 ones go to the bxCAN driver, the rest to Default_Handler.
#include <cstdint>

#include "bxcan.hpp"
#include "registers.hpp"
#include "startup.hpp"

extern "C" {
// Linker-script symbols (stm32f405.ld).
extern std::uint32_t __data_start[], __data_end[], __data_load[];
extern std::uint32_t __bss_start[], __bss_end[];
extern std::uint32_t __stack_bottom[], __stack_top[];
using InitFunction = void (*)();
extern InitFunction __init_array_start[], __init_array_end[];

[[noreturn]] void Reset_Handler();
void pa_runtime_init();
[[noreturn]] void Default_Handler();
void CAN1_TX_IRQHandler();
void CAN1_RX0_IRQHandler();
void CAN1_SCE_IRQHandler();

// The exception number of the fault that stopped the firmware, for a debugger to read.
volatile std::uint32_t g_fault_exception = 0;
}

namespace {
constexpr std::uint32_t kStackPaint = 0xA5A5A5A5u;
}

std::uint32_t stm32f405::stack_used_bytes() {
  const std::uint32_t* p = __stack_bottom;
  while (p < __stack_top && *p == kStackPaint) ++p;
  return static_cast<std::uint32_t>(reinterpret_cast<std::uintptr_t>(__stack_top) -
                                    reinterpret_cast<std::uintptr_t>(p));
}

// The FPU must be on before any compiled code might touch a floating-point register, so
// this runs first, in assembly; main() is called from here too (ISO C++ forbids calling it
// from C++). main() never returns; if it did, the firmware stops in Default_Handler.
extern "C" __attribute__((naked, noreturn)) void Reset_Handler() {
  asm volatile(
      "movw r0, #0xED88      \n"  // CPACR, 0xE000ED88
      "movt r0, #0xE000      \n"
      "ldr r1, [r0]          \n"
      "orr r1, r1, #0xF00000 \n"  // CP10 and CP11 full access
      "str r1, [r0]          \n"
      "dsb                   \n"
      "isb                   \n"
      "bl pa_runtime_init    \n"
      "bl main               \n"
      "b Default_Handler     \n");
}

extern "C" __attribute__((used)) void pa_runtime_init() {
  // The boot pins alias flash at 0; say explicitly where the table is.
  stm32f4::scb().VTOR = 0x08000000u;
  for (std::uint32_t *src = __data_load, *dst = __data_start; dst < __data_end;) *dst++ = *src++;
  for (std::uint32_t* p = __bss_start; p < __bss_end; ++p) *p = 0;
  std::uint32_t* sp;
  asm volatile("mov %0, sp" : "=r"(sp));
  for (std::uint32_t* p = __stack_bottom; p < sp - 16; ++p) *p = kStackPaint;
  for (InitFunction* f = __init_array_start; f < __init_array_end; ++f) (*f)();
}

// A fault stops the firmware here with interrupts off (no CAN traffic goes out, so the HIL
// plant sees the vehicle fall silent); a debugger finds the cause in g_fault_exception.
extern "C" void Default_Handler() {
  std::uint32_t ipsr;
  asm volatile("mrs %0, ipsr" : "=r"(ipsr));
  asm volatile("cpsid i" ::: "memory");
  g_fault_exception = ipsr & 0x1FFu;
  for (;;) asm volatile("wfi");
}

extern "C" void CAN1_TX_IRQHandler() { stm32f405::Can1::on_tx_interrupt(); }
extern "C" void CAN1_RX0_IRQHandler() { stm32f405::Can1::on_rx0_interrupt(); }
extern "C" void CAN1_SCE_IRQHandler() { stm32f405::Can1::on_status_change_error_interrupt(); }

// A pure virtual call is a bug; stop like any other fault (no abort(), no unwinding).
extern "C" void __cxa_pure_virtual() { Default_Handler(); }

namespace {

using Vector = void (*)();
constexpr unsigned kSystemVectors = 16;

struct VectorTable {
  std::uint32_t* initial_sp;
  Vector handlers[kSystemVectors - 1 + stm32f4::irq::count];
};

constexpr VectorTable make_vector_table() {
  VectorTable t{__stack_top, {}};
  for (Vector& v : t.handlers) v = Default_Handler;
  // System exceptions, numbered from 1 (Reset); slot 0 is the initial stack pointer.
  t.handlers[1 - 1] = Reset_Handler;
  for (unsigned reserved : {7u, 8u, 9u, 10u, 13u}) t.handlers[reserved - 1] = nullptr;
  // External interrupts start at exception 16.
  t.handlers[kSystemVectors - 1 + stm32f4::irq::can1_tx] = CAN1_TX_IRQHandler;
  t.handlers[kSystemVectors - 1 + stm32f4::irq::can1_rx0] = CAN1_RX0_IRQHandler;
  t.handlers[kSystemVectors - 1 + stm32f4::irq::can1_sce] = CAN1_SCE_IRQHandler;
  return t;
}

}  // namespace

extern "C" __attribute__((section(".isr_vector"), used)) constinit const VectorTable g_vector_table =
    make_vector_table();
