#include "semihosting.hpp"

namespace mps2::semihosting {
namespace {

// Operation numbers and reason codes from Arm's "Semihosting for AArch32 and AArch64".
constexpr std::uint32_t kSysWrite0 = 0x04;
constexpr std::uint32_t kSysExit = 0x18;
constexpr std::uint32_t kSysExitExtended = 0x20;
constexpr std::uint32_t kAdpStoppedApplicationExit = 0x20026;
constexpr std::uint32_t kAdpStoppedRunTimeErrorUnknown = 0x20023;

std::uint32_t call(std::uint32_t op, const void* arg) {
  register std::uint32_t r0 asm("r0") = op;
  register const void* r1 asm("r1") = arg;
  asm volatile("bkpt 0xAB" : "+r"(r0) : "r"(r1) : "memory");
  return r0;
}

}  // namespace

void write0(const char* text) { call(kSysWrite0, text); }

void exit(std::uint32_t code) {
  const std::uint32_t block[2] = {kAdpStoppedApplicationExit, code};
  call(kSysExitExtended, block);
  // Only reached when the host lacks SYS_EXIT_EXTENDED. On AArch32 SYS_EXIT takes the reason
  // itself in r1, so the status collapses to success or failure.
  const std::uint32_t reason = code == 0 ? kAdpStoppedApplicationExit : kAdpStoppedRunTimeErrorUnknown;
  call(kSysExit, reinterpret_cast<const void*>(reason));
  for (;;) asm volatile("bkpt 0");
}

}  // namespace mps2::semihosting
