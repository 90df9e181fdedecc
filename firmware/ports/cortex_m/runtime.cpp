#include "cortex_m/runtime.hpp"

extern "C" {
// Linker-script symbols (sections.ld).
extern std::uint32_t __data_start[], __data_end[], __data_load[];
extern std::uint32_t __bss_start[], __bss_end[];
extern std::uint32_t __stack_bottom[];
using InitFunction = void (*)();
extern InitFunction __init_array_start[], __init_array_end[];

void pa_runtime_init();
}

namespace {
constexpr std::uint32_t kStackPaint = 0xA5A5A5A5u;
}

// The FPU must be on before any compiled code might touch a floating-point register, so
// this runs first, in assembly; main() is called from here too (ISO C++ forbids calling it
// from C++).
extern "C" __attribute__((naked, noreturn)) void Reset_Handler() {
  asm volatile("movw r0, #0xED88      \n"  // CPACR, 0xE000ED88
               "movt r0, #0xE000      \n"
               "ldr r1, [r0]          \n"
               "orr r1, r1, #0xF00000 \n"  // CP10 and CP11 full access
               "str r1, [r0]          \n"
               "dsb                   \n"
               "isb                   \n"
               "bl pa_runtime_init    \n"
               "bl main               \n"
               "b pa_board_exit       \n");  // main's status is already in r0
}

extern "C" __attribute__((used)) void pa_runtime_init() {
  pa_board_reset_init();
  for (std::uint32_t *src = __data_load, *dst = __data_start; dst < __data_end;) *dst++ = *src++;
  for (std::uint32_t* p = __bss_start; p < __bss_end; ++p) *p = 0;

  // Paint below the live frame, leaving 64 bytes for the frames of the calls made while
  // painting (the compiler may turn this loop into a memset call).
  std::uint32_t* sp;
  asm volatile("mov %0, sp" : "=r"(sp));
  for (std::uint32_t* p = __stack_bottom; p < sp - 16; ++p) *p = kStackPaint;

  for (InitFunction* f = __init_array_start; f < __init_array_end; ++f) (*f)();
}

// A pure virtual call is a bug; stop like any other fault (no abort(), no unwinding).
extern "C" void __cxa_pure_virtual() { Default_Handler(); }

namespace cortex_m {

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

}  // namespace cortex_m
