// Instruction-exact timing on QEMU's mps2-an386.
//
// QEMU has no cycle model and no DWT cycle counter, but with `-icount shift=N` its virtual
// clock advances exactly 2^N ns per guest instruction. SysTick, clocked from the 25 MHz CPU
// clock (40 ns per count), reads that virtual clock, so a count difference converts exactly
// to instructions: instructions = counts * 40 / 2^N. With N = 10 one instruction is 25.6
// counts, far finer than one instruction. The 24-bit SysTick is widened to 64 bits by
// counting its wraps in the SysTick interrupt (one every 2^24 counts, about 655 000
// instructions). An instruction count is not a cycle count on silicon (a Cortex-M4 takes 1
// to ~12 cycles per instruction, mostly 1-2), so the figure is a machine-independent measure
// of a tick's work; the stm32f405 port measures real cycles with the DWT counter.
#pragma once

#include <cstdint>

#ifndef PA_MPS2_ICOUNT_SHIFT
#error "PA_MPS2_ICOUNT_SHIFT must match the -icount shift QEMU runs this image with"
#endif

namespace mps2 {

class InstructionCounter {
 public:
  static constexpr std::uint32_t kIcountShift = PA_MPS2_ICOUNT_SHIFT;
  static constexpr std::uint32_t kCpuClock_Hz = 25000000;  // SYSCLK of the MPS2 FPGA images
  static constexpr std::uint32_t kNsPerCount = 1000000000u / kCpuClock_Hz;
  static_assert(kNsPerCount * kCpuClock_Hz == 1000000000u, "whole nanoseconds per count");
  static_assert((1u << kIcountShift) > 4u * kNsPerCount,
                "one instruction must span several counts for the figure to be exact");

  // Starts SysTick free-running from the CPU clock with its wrap interrupt enabled.
  static void start();

  // SysTick counts since start(), widened to 64 bits; monotonic.
  static std::uint64_t counts();

  // Converts a count difference to instructions (exact under -icount shift=kIcountShift).
  static float instructions(std::uint64_t counts_elapsed) {
    return static_cast<float>(counts_elapsed * kNsPerCount) / static_cast<float>(1u << kIcountShift);
  }

  // Called from the SysTick exception.
  static void on_wrap();
};

}  // namespace mps2
