// Arm semihosting: the console and the exit code of the image under QEMU
// (-semihosting-config enable=on,target=native). Each call traps with `bkpt 0xAB`, which the
// debugger or emulator services; on a board without one it would fault, so only this
// QEMU-only port uses it.
#pragma once

#include <cstdint>

namespace mps2::semihosting {

// Writes a NUL-terminated string to the host's console (SYS_WRITE0).
void write0(const char* text);

// Reads the whole of the host file `path` (relative to the emulator's working directory) into
// `out` (SYS_OPEN in binary mode, SYS_FLEN, SYS_READ, SYS_CLOSE). Returns the file's length in
// bytes, which may exceed `capacity` (then only `capacity` bytes are read), or -1 when the file
// cannot be opened or read.
std::int32_t read_file(const char* path, std::uint8_t* out, std::uint32_t capacity);

// Ends the emulation with `code` as the process's exit status (SYS_EXIT_EXTENDED with
// ADP_Stopped_ApplicationExit; SYS_EXIT as a fallback, which can only tell 0 from 1).
[[noreturn]] void exit(std::uint32_t code);

}  // namespace mps2::semihosting
