// The InvenSense MPU-6000 (gyro + accelerometer on SPI; register map RM-MPU-6000A-00 rev 4.2,
// product specification PS-MPU-6000A-00 rev 3.4): its identity check, its initialisation as
// a register sequence, and the decoding of one 14-byte burst into a body-frame sample.
//
// The pure part of the IMU driver, run against any register bus (the board's SPI, or a fake
// one in the tests): the bus is a class with
//   bool read(std::uint8_t reg, std::uint8_t* data, std::size_t n);  // false: transfer failed
//   bool write(std::uint8_t reg, std::uint8_t value);
//   void delay_ms(std::uint32_t ms);  // start-up only, bounded
// No heap; initialisation is bounded (two reset waits and a fixed number of transfers).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "fw/drivers/orientation.hpp"
#include "fw/types.hpp"

namespace fw::drivers::mpu6000 {

namespace reg {
inline constexpr std::uint8_t smplrt_div = 0x19, config = 0x1A, gyro_config = 0x1B, accel_config = 0x1C,
                              int_pin_cfg = 0x37, int_enable = 0x38, accel_xout_h = 0x3B,
                              signal_path_reset = 0x68, user_ctrl = 0x6A, pwr_mgmt_1 = 0x6B,
                              pwr_mgmt_2 = 0x6C, who_am_i = 0x75;
}
inline constexpr std::uint8_t kReadBit = 0x80;  // SPI: set in the address byte of a read
inline constexpr std::uint8_t kWhoAmI = 0x68;
inline constexpr std::size_t kBurstBytes = 14;  // accel xyz, temperature, gyro xyz; big-endian int16
// The SPI clock limits (product specification 6.5): 1 MHz for every register, 20 MHz for the
// sensor and interrupt registers only.
inline constexpr std::uint32_t kSpiConfigHzMax = 1000000;
inline constexpr std::uint32_t kSpiSensorHzMax = 20000000;

// Measurement ranges; only the chip's four settings of each exist.
struct Range {
  std::uint16_t gyro_dps = 2000;  // 250, 500, 1000 or 2000
  std::uint8_t accel_g = 16;      // 2, 4, 8 or 16
};

// FS_SEL / AFS_SEL (bits 4:3 of GYRO_CONFIG / ACCEL_CONFIG): 0..3, or -1 for a range the chip lacks.
constexpr int gyro_fs_sel(std::uint16_t dps) {
  return dps == 250 ? 0 : dps == 500 ? 1 : dps == 1000 ? 2 : dps == 2000 ? 3 : -1;
}
constexpr int accel_afs_sel(std::uint8_t g) {
  return g == 2 ? 0 : g == 4 ? 1 : g == 8 ? 2 : g == 16 ? 3 : -1;
}
constexpr bool is_valid(const Range& r) {
  return gyro_fs_sel(r.gyro_dps) >= 0 && accel_afs_sel(r.accel_g) >= 0;
}

// Sensitivities: full scale over the int16 range (16.384 LSB/(deg/s) at 2000 deg/s, the
// datasheet's nominal 16.4; 2048 LSB/g at 16 g), as Betaflight scales them.
constexpr float gyro_radps_per_lsb(std::uint16_t dps) {
  return static_cast<float>(dps) / 32768.0f * (3.14159265358979f / 180.0f);
}
constexpr float accel_mps2_per_lsb(std::uint8_t g) { return static_cast<float>(g) * 9.80665f / 32768.0f; }

struct Step {
  std::uint8_t reg;
  std::uint8_t value;
  std::uint8_t delay_after_ms;  // the chip's settling time after this write
  bool verify;                  // read back and compared after the sequence
};

// The sequence after the identity check, in order (as Betaflight and PX4 do it): reset,
// signal-path reset, clock from the gyro's PLL, SPI only, every sensor on, 1 kHz output with
// the 188/184 Hz low-pass, the ranges, a data-ready pulse cleared by any read.
constexpr std::array<Step, 10> init_sequence(const Range& r) {
  const auto fs = static_cast<std::uint8_t>(gyro_fs_sel(r.gyro_dps) << 3);
  const auto afs = static_cast<std::uint8_t>(accel_afs_sel(r.accel_g) << 3);
  return {{
      {reg::pwr_mgmt_1, 0x80, 100, false},         // DEVICE_RESET
      {reg::signal_path_reset, 0x07, 100, false},  // gyro, accel, temperature paths
      {reg::pwr_mgmt_1, 0x03, 0, true},            // CLKSEL: PLL with the z gyro
      {reg::user_ctrl, 0x10, 0, true},             // I2C_IF_DIS: SPI only
      {reg::pwr_mgmt_2, 0x00, 0, true},            // no axis in standby
      {reg::smplrt_div, 0x00, 0, true},            // 1 kHz / (1 + 0)
      {reg::config, 0x01, 0, true},                // DLPF_CFG 1: 1 kHz internal rate
      {reg::gyro_config, fs, 0, true},
      {reg::accel_config, afs, 0, true},
      {reg::int_pin_cfg, 0x10, 0, true},  // INT_RD_CLEAR; active high, push-pull, 50 us pulse
  }};
}
// Enabled last, once everything else is known to be right.
inline constexpr Step kEnableDataReady{reg::int_enable, 0x01, 0, true};

enum class Status : std::uint8_t {
  ok = 0,
  no_response,      // WHO_AM_I read 0x00 or 0xFF: nothing drives MISO (absent, unpowered, wrong CS)
  wrong_identity,   // another chip answered
  bus_error,        // a transfer did not complete
  bad_range,        // the board table asks for a range the chip lacks
  config_rejected,  // a register read back differently from what was written
};

constexpr const char* to_string(Status s) {
  switch (s) {
    case Status::ok: return "ok";
    case Status::no_response: return "no_response";
    case Status::wrong_identity: return "wrong_identity";
    case Status::bus_error: return "bus_error";
    case Status::bad_range: return "bad_range";
    case Status::config_rejected: return "config_rejected";
  }
  return "unknown";
}

struct InitResult {
  Status status = Status::no_response;
  std::uint8_t who_am_i = 0;         // what the identity register read
  std::uint8_t failed_register = 0;  // for config_rejected and bus_error
};

template <class Bus>
InitResult init(Bus& bus, const Range& range) {
  InitResult r{};
  if (!is_valid(range)) {
    r.status = Status::bad_range;
    return r;
  }
  std::uint8_t id = 0;
  if (!bus.read(reg::who_am_i, &id, 1)) {
    r.status = Status::bus_error;
    r.failed_register = reg::who_am_i;
    return r;
  }
  r.who_am_i = id;
  if (id == 0x00 || id == 0xFF) {
    r.status = Status::no_response;
    return r;
  }
  if (id != kWhoAmI) {
    r.status = Status::wrong_identity;
    return r;
  }
  const auto steps = init_sequence(range);
  for (const Step& s : steps) {
    if (!bus.write(s.reg, s.value)) {
      r.status = Status::bus_error;
      r.failed_register = s.reg;
      return r;
    }
    if (s.delay_after_ms != 0) bus.delay_ms(s.delay_after_ms);
  }
  for (const Step& s : steps) {
    if (!s.verify) continue;
    std::uint8_t value = 0;
    if (!bus.read(s.reg, &value, 1) || value != s.value) {
      r.status = Status::config_rejected;
      r.failed_register = s.reg;
      return r;
    }
  }
  if (!bus.write(kEnableDataReady.reg, kEnableDataReady.value)) {
    r.status = Status::bus_error;
    r.failed_register = kEnableDataReady.reg;
    return r;
  }
  r.status = Status::ok;
  return r;
}

// One burst in the chip's axes, as read.
struct Raw {
  std::array<std::int16_t, 3> accel{};
  std::int16_t temperature = 0;
  std::array<std::int16_t, 3> gyro{};
};

constexpr std::int16_t be16(const std::uint8_t* p) {
  return static_cast<std::int16_t>(static_cast<std::uint16_t>((p[0] << 8) | p[1]));
}

// False for a burst of all 0x00 or all 0xFF bytes: no chip drove the bus (a real sample
// always has gravity or noise in it).
constexpr bool parse(const std::array<std::uint8_t, kBurstBytes>& burst, Raw& out) {
  bool all_zero = true, all_ones = true;
  for (std::uint8_t b : burst) {
    all_zero = all_zero && b == 0x00;
    all_ones = all_ones && b == 0xFF;
  }
  if (all_zero || all_ones) return false;
  for (int i = 0; i < 3; ++i) {
    out.accel[i] = be16(&burst[2 * i]);
    out.gyro[i] = be16(&burst[8 + 2 * i]);
  }
  out.temperature = be16(&burst[6]);
  return true;
}

// Scales a raw burst and turns it into the body frame (the board table's mounting).
constexpr ImuSample to_sample(const Raw& raw, const Range& range, const AxisMap& mounting,
                              std::uint32_t t_us) {
  const float g_scale = gyro_radps_per_lsb(range.gyro_dps);
  const float a_scale = accel_mps2_per_lsb(range.accel_g);
  Vec3f gyro{}, accel{};
  for (int i = 0; i < 3; ++i) {
    gyro[i] = static_cast<float>(raw.gyro[i]) * g_scale;
    accel[i] = static_cast<float>(raw.accel[i]) * a_scale;
  }
  ImuSample s;
  s.t_us = t_us;
  s.gyro_radps = to_body(mounting, gyro);
  s.accel_mps2 = to_body(mounting, accel);
  return s;
}

}  // namespace fw::drivers::mpu6000
