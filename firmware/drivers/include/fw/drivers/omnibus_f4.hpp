// The board table of the flight image: the Airbot Omnibus F4 (STM32F405RG, 8 MHz crystal,
// MPU-6000 on SPI1), from Betaflight's unified target AIRB-OMNIBUSF4.config
// (github.com/betaflight/unified-targets, configs/default/AIRB-OMNIBUSF4.config): every pin,
// timer, DMA stream, the sensor's mounting and the battery divider in one place, read by the
// drivers in firmware/ports/stm32f405. Host-compilable, so the tests check the table itself.
#pragma once

#include <cstdint>

#include "fw/drivers/dshot.hpp"
#include "fw/drivers/mpu6000.hpp"
#include "fw/drivers/orientation.hpp"
#include "fw/saturating.hpp"

namespace fw::drivers::omnibus_f4 {

inline constexpr const char* kName = "omnibusf4";  // make flash BOARD=omnibusf4

struct Pin {
  char port;  // 'A'..'C'
  std::uint8_t number;
  std::uint8_t alternate_function;  // 0 when the pin is not an alternate function
};

// IMU: MPU-6000 on SPI1 (SCK PA5, MISO PA6, MOSI PA7, CS PA4), data ready on PC4 (EXTI4).
inline constexpr Pin kSpiSck{'A', 5, 5}, kSpiMiso{'A', 6, 5}, kSpiMosi{'A', 7, 5}, kImuCs{'A', 4, 0};
inline constexpr Pin kImuDataReady{'C', 4, 0};
// Betaflight's gyro_1_sensor_align = CW180: the chip is turned half a turn on the board.
inline constexpr AxisMap kImuMounting = kCw180;
// 2000 deg/s and 16 g: a caught pole peaks near 60 m/s^2 and a touchdown near 100 (config.hpp),
// above the 8 g range.
inline constexpr mpu6000::Range kImuRange{2000, 16};
static_assert(mpu6000::is_valid(kImuRange) && is_rotation(kImuMounting));

// Motors 1-4 (Betaflight's numbering, the board's M1-M4 pads) and the timer channel each is:
// M1 PB0 TIM3_CH3, M2 PB1 TIM3_CH4, M3 PA3 TIM2_CH4, M4 PA2 TIM2_CH3. Each timer's update
// DMA bursts both its compare registers per bit: TIM3_UP is DMA1 stream 2 channel 5, TIM2_UP
// DMA1 stream 1 channel 3 (RM0090 table 42).
struct Motor {
  Pin pin;
  std::uint8_t timer;    // 2 or 3
  std::uint8_t channel;  // 3 or 4
};
inline constexpr Motor kMotors[4] = {
    {{'B', 0, 2}, 3, 3},
    {{'B', 1, 2}, 3, 4},
    {{'A', 3, 1}, 2, 4},
    {{'A', 2, 1}, 2, 3},
};
// fw::Mixer's motor i (PX4 quad-x: 0 front-right, 1 rear-left, 2 front-left, 3 rear-right)
// drives the board's pad kMotorPad[i]. Betaflight's quad-x is 1 rear-right, 2 front-right,
// 3 rear-left, 4 front-left, so a frame wired for Betaflight needs no rewiring.
inline constexpr std::uint8_t kMotorPad[4] = {1, 2, 3, 0};  // index into kMotors
// TIM2 and TIM3 are on APB1: 84 MHz timer clock at SYSCLK 168 MHz.
inline constexpr std::uint32_t kMotorTimerHz = 84000000;
inline constexpr dshot::BitTiming kDshot600 = dshot::bit_timing(kMotorTimerHz, dshot::kDshot600BitRate);
static_assert(kDshot600.valid);

// Battery: PC2 is ADC123_IN12 behind a 10k/1k divider (Betaflight's vbat_scale 110).
inline constexpr Pin kBatteryPin{'C', 2, 0};
inline constexpr std::uint8_t kBatteryAdcChannel = 12;
inline constexpr std::uint32_t kBatteryDividerX10 = 110;
inline constexpr std::uint32_t kAdcReferenceMv = 3300;

// Millivolts at the battery for a 12-bit ADC reading (saturates at the 16-bit field).
constexpr std::uint16_t battery_mv(std::uint16_t adc) {
  const std::uint32_t mv =
      (static_cast<std::uint32_t>(adc & 0x0FFFu) * kAdcReferenceMv * kBatteryDividerX10 + 20475u) /
      (4095u * 10u);
  return saturate_cast<std::uint16_t>(mv);
}

// Status LED on PB5, lit when driven low.
inline constexpr Pin kLed{'B', 5, 0};
inline constexpr bool kLedActiveLow = true;

// The ground link: USART1 (TX PA9, RX PA10, AF7) to a radio modem at 115200 baud carrying
// pa/serial_frame.hpp frames; the text console: USART3 (TX PB10, RX PB11, AF7).
inline constexpr Pin kLinkTx{'A', 9, 7}, kLinkRx{'A', 10, 7};
inline constexpr Pin kConsoleTx{'B', 10, 7}, kConsoleRx{'B', 11, 7};
inline constexpr std::uint32_t kLinkBaud = 115200, kConsoleBaud = 115200;

}  // namespace fw::drivers::omnibus_f4
