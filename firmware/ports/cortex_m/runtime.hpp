// The bare C++ runtime that every Cortex-M4F image here shares: no C library start files, no
// heap. Reset_Handler enables the FPU, runs pa_runtime_init (the board's reset hook, then
// .data copied, .bss zeroed, the unused stack painted, the static constructors run) and calls
// main(); when main returns its status goes to the board's exit hook. sections.ld lays out
// the memory this code initialises.
//
// What each board supplies: its vector table (built with default_vector_table()), the two
// hooks and the fault handler below.
#pragma once

#include <cstdint>
#include <initializer_list>

extern "C" {
// The top of the main stack (sections.ld): the vector table's initial stack pointer.
extern std::uint32_t __stack_top[];

// Defined here: the reset entry point, for the board's vector table.
[[noreturn]] void Reset_Handler();

// Defined by the board. pa_board_reset_init runs first thing after the FPU is on, before
// .data and .bss are set up, so it may write registers but must not read or write static
// variables (nor call code that does). pa_board_exit receives main()'s return value.
void pa_board_reset_init();
[[noreturn]] void pa_board_exit(int status);

// Defined by the board: every exception the image does not handle, and a pure virtual call.
[[noreturn]] void Default_Handler();
}

namespace cortex_m {

// The main stack reserved by the linker script (counted in the image's RAM figure).
std::uint32_t stack_size_bytes();

// The main stack's high-water mark so far: start-up paints the unused stack with a pattern and
// this finds the deepest word overwritten (it scans only the untouched part).
std::uint32_t stack_used_bytes();

// ---------------------------------------------------------------------------------------
// The vector table (ARMv7-M ARM, section B1.5.3): the initial stack pointer, then one handler
// per exception number from 1 (Reset); external interrupt n is exception 16 + n.
// ---------------------------------------------------------------------------------------
using Vector = void (*)();
inline constexpr unsigned kSystemExceptions = 16;  // exception numbers 0 .. 15

namespace exception {
inline constexpr unsigned reset = 1, nmi = 2, hard_fault = 3, mem_manage = 4, bus_fault = 5, usage_fault = 6,
                          sv_call = 11, debug_monitor = 12, pend_sv = 14, sys_tick = 15;
}

template <unsigned IrqCount>
struct VectorTable {
  std::uint32_t* initial_sp;
  Vector handlers[kSystemExceptions - 1 + IrqCount];

  constexpr Vector& exception(unsigned number) { return handlers[number - 1]; }
  constexpr Vector& irq(unsigned line) { return handlers[kSystemExceptions - 1 + line]; }
};

// A table with the stack at __stack_top, Reset_Handler at reset, the reserved entries (7-10
// and 13) empty and every other exception and interrupt sent to Default_Handler; the board
// then installs its own handlers.
template <unsigned IrqCount>
constexpr VectorTable<IrqCount> default_vector_table() {
  VectorTable<IrqCount> t{__stack_top, {}};
  for (Vector& v : t.handlers) v = Default_Handler;
  t.exception(exception::reset) = Reset_Handler;
  for (unsigned reserved : {7u, 8u, 9u, 10u, 13u}) t.exception(reserved) = nullptr;
  return t;
}

}  // namespace cortex_m
