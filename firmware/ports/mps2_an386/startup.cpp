// Reset, vector table and the bare C++ runtime of the mps2-an386 image: no C library start
// files, no heap. Reset enables the FPU, copies .data, zeroes .bss, paints the stack so its
// high-water mark can be measured, runs the static constructors and calls main().
#include <cstdint>

#include "console.hpp"
#include "instruction_counter.hpp"
#include "semihosting.hpp"
#include "startup.hpp"

extern "C" {
// Linker-script symbols (mps2_an386.ld).
extern std::uint32_t __data_start[], __data_end[], __data_load[];
extern std::uint32_t __bss_start[], __bss_end[];
extern std::uint32_t __stack_bottom[], __stack_top[];
using InitFunction = void (*)();
extern InitFunction __init_array_start[], __init_array_end[];

[[noreturn]] void Reset_Handler();
void pa_runtime_init();
[[noreturn]] void pa_runtime_exit(int status);
void Default_Handler();
void SysTick_Handler();
}

namespace {
constexpr std::uint32_t kStackPaint = 0xA5A5A5A5u;
}

// The FPU must be on before any compiled code might touch a floating-point register, so
// this runs first, in assembly; main() is called from here too (ISO C++ forbids calling it
// from C++).
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
      "b pa_runtime_exit     \n");  // main's status is already in r0
}

extern "C" __attribute__((used)) void pa_runtime_init() {
  for (std::uint32_t *src = __data_load, *dst = __data_start; dst < __data_end;) *dst++ = *src++;
  for (std::uint32_t* p = __bss_start; p < __bss_end; ++p) *p = 0;

  std::uint32_t* sp;
  asm volatile("mov %0, sp" : "=r"(sp));
  for (std::uint32_t* p = __stack_bottom; p < sp - 16; ++p) *p = kStackPaint;

  for (InitFunction* f = __init_array_start; f < __init_array_end; ++f) (*f)();
}

extern "C" __attribute__((used)) void pa_runtime_exit(int status) { mps2::semihosting::exit(static_cast<std::uint32_t>(status)); }

namespace mps2 {

std::uint32_t stack_size_bytes() {
  return static_cast<std::uint32_t>(reinterpret_cast<std::uintptr_t>(__stack_top) -
                                    reinterpret_cast<std::uintptr_t>(__stack_bottom));
}

std::uint32_t stack_used_bytes() {
  const std::uint32_t* p = __stack_bottom;
  while (p < __stack_top && *p == kStackPaint) ++p;
  return static_cast<std::uint32_t>(reinterpret_cast<std::uintptr_t>(__stack_top) -
                                    reinterpret_cast<std::uintptr_t>(p));
}

}  // namespace mps2

// An unexpected exception ends the run as a failure that names it, rather than hanging QEMU.
extern "C" void Default_Handler() {
  std::uint32_t ipsr;
  asm volatile("mrs %0, ipsr" : "=r"(ipsr));
  mps2::ConsoleLine().text("selftest: fail exception ").u32(ipsr & 0x1FFu).emit();
  mps2::semihosting::exit(1);
}

extern "C" void SysTick_Handler() { mps2::InstructionCounter::on_wrap(); }

// A pure virtual call is a bug; trap it like any other fault (no abort(), no unwinding).
extern "C" void __cxa_pure_virtual() { Default_Handler(); }

namespace {
using Vector = void (*)();
constexpr int kSystemVectors = 16;
constexpr int kIrqVectors = 32;  // QEMU's AN385/AN386 interrupt controller has 32 lines

struct VectorTable {
  std::uint32_t* initial_sp;
  Vector handlers[kSystemVectors - 1 + kIrqVectors];
};
}  // namespace

extern "C" __attribute__((section(".isr_vector"), used)) const VectorTable g_vector_table = {
    __stack_top, {
    Reset_Handler,
    Default_Handler,  // NMI
    Default_Handler,  // HardFault
    Default_Handler,  // MemManage
    Default_Handler,  // BusFault
    Default_Handler,  // UsageFault
    nullptr, nullptr, nullptr, nullptr,
    Default_Handler,  // SVCall
    Default_Handler,  // DebugMonitor
    nullptr,
    Default_Handler,  // PendSV
    SysTick_Handler,
    // External interrupts: none are enabled by this image.
    Default_Handler, Default_Handler, Default_Handler, Default_Handler, Default_Handler, Default_Handler,
    Default_Handler, Default_Handler, Default_Handler, Default_Handler, Default_Handler, Default_Handler,
    Default_Handler, Default_Handler, Default_Handler, Default_Handler, Default_Handler, Default_Handler,
    Default_Handler, Default_Handler, Default_Handler, Default_Handler, Default_Handler, Default_Handler,
    Default_Handler, Default_Handler, Default_Handler, Default_Handler, Default_Handler, Default_Handler,
    Default_Handler, Default_Handler,
}};
