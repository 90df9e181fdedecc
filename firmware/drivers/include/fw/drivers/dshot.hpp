// DShot, the digital ESC protocol: each motor gets a 16-bit frame, most significant bit
// first, as pulses of a fixed bit period whose high time says 0 (3/8 of the period) or 1
// (3/4 of it). The frame is an 11-bit value (0: motor stop, 1-47: ESC commands, 48-2047:
// throttle), one telemetry-request bit and a 4-bit checksum over the other 12 bits.
//
// The pure part of the motor output: frame encoding, bit timings in timer ticks and the
// compare values a timer's DMA writes, one per bit. Host-testable; the register poking is in
// firmware/ports/stm32f405/dshot_output.*. No heap, constant time.
#pragma once

#include <array>
#include <cstdint>

namespace fw::drivers::dshot {

inline constexpr std::uint16_t kMotorStop = 0;
inline constexpr std::uint16_t kThrottleMin = 48;
inline constexpr std::uint16_t kThrottleMax = 2047;
inline constexpr std::uint32_t kBitsPerFrame = 16;
inline constexpr std::uint32_t kDshot600BitRate = 600000;

// The 4-bit checksum of the 12 bits `value_and_telemetry` (throttle << 1 | telemetry).
constexpr std::uint16_t crc(std::uint16_t value_and_telemetry) {
  const auto v = static_cast<std::uint16_t>(value_and_telemetry & 0x0FFFu);
  return static_cast<std::uint16_t>((v ^ (v >> 4) ^ (v >> 8)) & 0x0Fu);
}

// The 16-bit frame for an 11-bit value (values above 2047 are clamped, never wrapped: a
// wrapped throttle would be a command or a motor stop).
constexpr std::uint16_t frame(std::uint16_t value, bool telemetry) {
  const std::uint16_t v = value > kThrottleMax ? kThrottleMax : value;
  const auto payload = static_cast<std::uint16_t>((v << 1) | (telemetry ? 1u : 0u));
  return static_cast<std::uint16_t>((payload << 4) | crc(payload));
}

// The DShot value for a normalised motor command: motor stop unless enabled, else 0..1 onto
// 48..2047. Out-of-range commands are clamped; a non-finite one gives the lowest throttle.
constexpr std::uint16_t value_from_command(float command, bool enabled) {
  if (!enabled) return kMotorStop;
  if (!(command > 0.0f)) return kThrottleMin;  // also NaN
  if (command >= 1.0f) return kThrottleMax;
  const float span = static_cast<float>(kThrottleMax - kThrottleMin);
  return static_cast<std::uint16_t>(kThrottleMin + static_cast<std::uint16_t>(command * span + 0.5f));
}

// Pulse widths in ticks of the timer that generates them.
struct BitTiming {
  std::uint32_t period_ticks = 0;  // one bit (the timer's ARR is period_ticks - 1)
  std::uint32_t t0h_ticks = 0;     // high time of a 0 bit, 3/8 of the period
  std::uint32_t t1h_ticks = 0;     // high time of a 1 bit, 3/4 of the period
  bool valid = false;              // the period is within 2 % of the bit rate and both pulses are told apart
};

// Rounded to the nearest tick; `valid` false when the timer clock is too slow or uneven.
constexpr BitTiming bit_timing(std::uint32_t timer_hz, std::uint32_t bit_rate) {
  BitTiming t{};
  if (bit_rate == 0 || timer_hz < bit_rate) return t;
  t.period_ticks = (timer_hz + bit_rate / 2u) / bit_rate;
  t.t0h_ticks = (3u * t.period_ticks + 4u) / 8u;
  t.t1h_ticks = (3u * t.period_ticks + 2u) / 4u;
  const std::uint64_t actual_rate_x100 = 100ull * timer_hz / t.period_ticks;
  const std::uint64_t wanted_x100 = 100ull * bit_rate;
  const std::uint64_t error =
      actual_rate_x100 > wanted_x100 ? actual_rate_x100 - wanted_x100 : wanted_x100 - actual_rate_x100;
  t.valid = t.period_ticks >= 8u && error * 50u <= wanted_x100 && t.t0h_ticks < t.t1h_ticks &&
            t.t1h_ticks < t.period_ticks;
  return t;
}

// The compare value of each bit, most significant first; the DMA writes one per timer period.
// Two trailing zeros hold the line low after the frame (the ESC's frame gap).
inline constexpr std::uint32_t kSlotsPerFrame = kBitsPerFrame + 2;
using Pulses = std::array<std::uint32_t, kSlotsPerFrame>;

constexpr Pulses pulses(std::uint16_t frame_bits, const BitTiming& timing) {
  Pulses p{};
  for (std::uint32_t bit = 0; bit < kBitsPerFrame; ++bit) {
    const bool one = ((frame_bits >> (kBitsPerFrame - 1u - bit)) & 1u) != 0u;
    p[bit] = one ? timing.t1h_ticks : timing.t0h_ticks;
  }
  return p;
}

}  // namespace fw::drivers::dshot
