// Wrap-safe sequence-number arithmetic for the small counters carried in frames
// (4-bit setpoint sequence, 8-bit command and heartbeat sequences).
// Freestanding: no heap, no exceptions, no OS.
#pragma once

#include <cstdint>

namespace pa {

// Serial-number arithmetic (RFC 1982 style) on a counter of `Bits` bits.
template <unsigned Bits>
struct SequenceSpace {
  static_assert(Bits >= 2 && Bits <= 16, "sequence counters are 2 to 16 bits wide");
  static constexpr std::uint32_t modulus = 1u << Bits;
  static constexpr std::uint32_t mask = modulus - 1u;
  static constexpr std::uint32_t half = modulus / 2u;

  static constexpr std::uint32_t next(std::uint32_t s) { return (s + 1u) & mask; }

  // Forward distance from `from` to `to`, modulo 2^Bits.
  static constexpr std::uint32_t distance(std::uint32_t from, std::uint32_t to) { return (to - from) & mask; }

  // `candidate` is newer than `reference` when it lies less than half the space ahead.
  // Equal numbers are not newer (a repeated frame), nor is anything half or more ahead
  // (it is as likely an old frame replayed as a new one).
  static constexpr bool is_newer(std::uint32_t candidate, std::uint32_t reference) {
    const std::uint32_t d = distance(reference, candidate);
    return d != 0u && d < half;
  }
};

using SetpointSeq = SequenceSpace<4>;
using CommandSeq = SequenceSpace<8>;
using HeartbeatSeq = SequenceSpace<8>;

static_assert(SetpointSeq::is_newer(0, 15), "wraps forward");
static_assert(!SetpointSeq::is_newer(15, 0), "behind is not newer");
static_assert(!SetpointSeq::is_newer(3, 3), "equal is not newer");
static_assert(!SetpointSeq::is_newer(8, 0), "half the space ahead is ambiguous, so not newer");

// Wrap-safe comparison of free-running 32-bit microsecond clocks.
constexpr std::int32_t elapsed_us(std::uint32_t now_us, std::uint32_t then_us) {
  return static_cast<std::int32_t>(now_us - then_us);
}

}  // namespace pa
