// The board's MPU-6000 on SPI1 with its data-ready line on EXTI4 (fw/drivers/omnibus_f4.hpp):
// initialisation through the pure register sequence (fw/drivers/mpu6000.hpp) at a config-safe
// SPI clock, then 1 kHz data-ready interrupts that stamp the sample time and start the burst
// read, whose completion flags the main
// loop, which decodes the 14-byte burst read at the fast clock into the body frame.
//
// Initialisation polls the SPI (start-up only, every wait bounded); the 1 kHz burst runs on
// the SPI's receive interrupt, one byte each, so the main loop never waits for the bus.
// No heap.
#pragma once

#include <cstdint>

#include "fw/drivers/mpu6000.hpp"
#include "fw/types.hpp"

namespace stm32f405 {

struct ImuStats {
  std::uint32_t data_ready = 0;    // interrupts seen
  std::uint32_t samples = 0;       // bursts read and decoded
  std::uint32_t missed = 0;        // a data-ready came before the last sample was taken
  std::uint32_t bad_bursts = 0;    // all 0x00 or all 0xFF: the chip stopped answering
  std::uint32_t bus_timeouts = 0;  // an SPI transfer did not complete in time
};

class Imu {
 public:
  // `apb2_hz`: SPI1's clock. Returns the chip's answer; data-ready interrupts run only when ok.
  static fw::drivers::mpu6000::InitResult init(std::uint32_t apb2_hz);
  // Takes the sample flagged by the last data-ready interrupt; false when there is none or
  // the burst was unusable (counted).
  static bool take_sample(fw::ImuSample& out);
  static bool sample_pending();
  static ImuStats stats();
  static void on_data_ready_interrupt();  // EXTI4
  static void on_spi_interrupt();         // SPI1
};

}  // namespace stm32f405
