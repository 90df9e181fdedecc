// Standard ESC PWM, the fallback for ESCs without DShot: a 1000 us pulse is motor stop, 2000 us
// full throttle, repeated at 490 Hz (Betaflight's default for this protocol). The pure part:
// pulse widths for normalised commands and the timer set-up that gives 1 us ticks.
// Host-testable; the register poking is in firmware/ports/stm32f405/pwm_output.cpp.
#pragma once

#include <cstdint>

namespace fw::drivers::pwm {

inline constexpr std::uint16_t kStopUs = 1000;
inline constexpr std::uint16_t kFullUs = 2000;
inline constexpr std::uint32_t kRateHz = 490;

// Motor stop unless enabled; 0..1 onto 1000..2000 us, clamped; a non-finite command gives the
// lowest throttle, as DShot does.
constexpr std::uint16_t pulse_us(float command, bool enabled) {
  if (!enabled || !(command > 0.0f)) return kStopUs;
  if (command >= 1.0f) return kFullUs;
  return static_cast<std::uint16_t>(kStopUs + static_cast<std::uint16_t>(command * 1000.0f + 0.5f));
}

struct Timing {
  std::uint32_t prescaler = 0;     // PSC: the timer counts at timer_hz / (PSC + 1) = 1 MHz
  std::uint32_t period_ticks = 0;  // ARR + 1, in microseconds
  bool valid = false;              // the timer clock is a whole number of MHz (and not 0)
};

constexpr Timing timing(std::uint32_t timer_hz, std::uint32_t rate_hz) {
  Timing t{};
  if (timer_hz < 1000000u || timer_hz % 1000000u != 0u || rate_hz == 0u) return t;
  t.prescaler = timer_hz / 1000000u - 1u;
  t.period_ticks = 1000000u / rate_hz;
  t.valid = t.period_ticks > kFullUs && t.prescaler <= 0xFFFFu;
  return t;
}

}  // namespace fw::drivers::pwm
