// DShot600 on the board's four motor pads (fw/drivers/omnibus_f4.hpp): TIM3 channels 3-4 and
// TIM2 channels 3-4 in PWM mode at one bit period, each timer's update event requesting a DMA
// burst that writes both its compare registers with the next bit's pulse width (DMAR/DCR).
// write() fills the pulse buffers from the pure encoder (fw/drivers/dshot.hpp) and restarts
// both DMA streams: a frame is 18 bit periods (30 us), so it is long done by the next 1 kHz
// tick; a stream still busy is left alone and the frame counted as skipped. Non-blocking,
// no heap.
#pragma once

#include <array>
#include <cstdint>

namespace stm32f405 {

struct DshotStats {
  std::uint32_t frames = 0;                    // frame sets started (all four motors)
  std::uint32_t skipped = 0;                   // a stream was still busy with the last frame
  std::uint32_t dma_errors = 0;                // transfer-error flags seen
  std::array<std::uint16_t, 4> last_values{};  // by board pad M1..M4
};

class DshotOutput {
 public:
  // `timer_hz`: TIM2/TIM3's clock (ClockReport::apb1_timer_hz). False when no DShot600
  // timing fits that clock; the outputs then stay low (no signal: the ESCs do not arm).
  static bool init(std::uint32_t timer_hz);
  // DShot values (0 stop, 48..2047 throttle) by board pad M1..M4.
  static void write(const std::array<std::uint16_t, 4>& pad_values);
  static const DshotStats& stats();
};

}  // namespace stm32f405
