// The flight image's motor output on the board's four motor pads (fw/drivers/omnibus_f4.hpp),
// TIM3 channels 3-4 and TIM2 channels 3-4. Each image links one implementation:
//
// - dshot_output.cpp (fw_stm32f405_flight): DShot600. Each timer runs in PWM mode at one bit
//   period and its update event requests a DMA burst that writes both compare registers with
//   the next bit's pulse width (DMAR/DCR). write() fills the pulse buffers from the pure
//   encoder (fw/drivers/dshot.hpp) and restarts both DMA streams; a frame is 18 bit periods
//   (30 us), long done by the next 1 kHz tick; a stream still busy is left alone and the frame
//   counted as skipped.
// - pwm_output.cpp (fw_stm32f405_flight_pwm): standard 1000-2000 us PWM at 490 Hz for ESCs
//   without DShot (fw/drivers/pwm.hpp); write() sets the compare registers, taken at the next
//   period.
//
// Non-blocking, no heap.
#pragma once

#include <array>
#include <cstdint>

#include "fw/types.hpp"

namespace stm32f405 {

struct MotorOutputStats {
  std::uint32_t frames = 0;   // outputs written (all four motors)
  std::uint32_t skipped = 0;  // DShot: a DMA stream was still busy with the last frame
  std::uint32_t dma_errors = 0;
  std::array<std::uint16_t, 4> last_values{};  // by board pad M1..M4: DShot value or PWM us
};

class MotorOutput {
 public:
  static const char* name();  // "dshot" or "pwm_us", the unit of last_values
  // `timer_hz`: TIM2/TIM3's clock (ClockReport::apb1_timer_hz). False when no timing fits that
  // clock; the outputs then stay low (no signal: the ESCs do not arm).
  static bool init(std::uint32_t timer_hz);
  // Motor commands in the mixer's order (normalised 0..1), sent to their pads.
  static void write(const fw::Motors& command, bool enabled);
  static void stop() { write(fw::Motors{}, false); }
  static const MotorOutputStats& stats();
};

}  // namespace stm32f405
