#include "semihosting.hpp"

namespace mps2::semihosting {
namespace {

// Operation numbers and reason codes from Arm's "Semihosting for AArch32 and AArch64".
constexpr std::uint32_t kSysOpen = 0x01;
constexpr std::uint32_t kSysClose = 0x02;
constexpr std::uint32_t kSysWrite0 = 0x04;
constexpr std::uint32_t kSysRead = 0x06;
constexpr std::uint32_t kSysFlen = 0x0C;
constexpr std::uint32_t kOpenModeReadBinary = 1;  // fopen's "rb"
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

std::int32_t read_file(const char* path, std::uint8_t* out, std::uint32_t capacity) {
  std::uint32_t path_length = 0;
  while (path[path_length] != '\0') ++path_length;
  const std::uint32_t open_block[3] = {reinterpret_cast<std::uint32_t>(path), kOpenModeReadBinary,
                                       path_length};
  const auto handle = static_cast<std::int32_t>(call(kSysOpen, open_block));
  if (handle < 0) return -1;
  const std::uint32_t handle_block[1] = {static_cast<std::uint32_t>(handle)};
  const auto length = static_cast<std::int32_t>(call(kSysFlen, handle_block));
  std::int32_t result = length;
  if (length >= 0) {
    const std::uint32_t wanted =
        static_cast<std::uint32_t>(length) < capacity ? static_cast<std::uint32_t>(length) : capacity;
    const std::uint32_t read_block[3] = {static_cast<std::uint32_t>(handle),
                                         reinterpret_cast<std::uint32_t>(out), wanted};
    // SYS_READ returns how many of the bytes asked for it did not read.
    if (wanted != 0u && call(kSysRead, read_block) != 0u) result = -1;
  }
  call(kSysClose, handle_block);
  return result;
}

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
