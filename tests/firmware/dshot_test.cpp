// DShot frames against hand-computed ones, and the bit timings against the timer clock.
#include <catch2/catch.hpp>

#include <limits>

#include "fw/drivers/dshot.hpp"
#include "fw/drivers/omnibus_f4.hpp"

namespace dshot = fw::drivers::dshot;

TEST_CASE("dshot frames match hand-computed ones") {
  // Throttle 1046, no telemetry: value+telemetry = 1046 << 1 = 0x82C;
  // CRC = (0x82C ^ 0x082 ^ 0x008) & 0xF = 0x6 -> 1000 0010 1100 0110.
  CHECK(dshot::frame(1046, false) == 0x82C6);
  // With the telemetry bit: 0x82D; CRC = (0x82D ^ 0x082 ^ 0x008) & 0xF = 0x7.
  CHECK(dshot::frame(1046, true) == 0x82D7);
  // Motor stop is all zeros, CRC included.
  CHECK(dshot::frame(0, false) == 0x0000);
  // Lowest throttle 48: 48 << 1 = 0x060; CRC = (0x060 ^ 0x006 ^ 0x000) & 0xF = 0x6.
  CHECK(dshot::frame(48, false) == 0x0606);
  // Full throttle 2047: 0xFFE; CRC = (0xFFE ^ 0x0FF ^ 0x00F) & 0xF = 0xE ^ 0xF ^ 0xF = 0xE.
  CHECK(dshot::frame(2047, false) == 0xFFEE);
  // Values above 11 bits are clamped to full throttle, never wrapped to a command.
  CHECK(dshot::frame(2048, false) == dshot::frame(2047, false));
  CHECK(dshot::frame(0xFFFF, false) == dshot::frame(2047, false));
}

TEST_CASE("the checksum makes the xor of the frame's four nibbles zero") {
  for (std::uint16_t v = 0; v <= 2047; ++v) {
    for (bool telemetry : {false, true}) {
      const std::uint16_t f = dshot::frame(v, telemetry);
      CHECK(((f ^ (f >> 4) ^ (f >> 8) ^ (f >> 12)) & 0xF) == 0);
      CHECK((f >> 5) == v);
      CHECK(((f >> 4) & 1) == (telemetry ? 1 : 0));
    }
  }
}

TEST_CASE("motor commands map onto the throttle range and stop when disabled") {
  CHECK(dshot::value_from_command(0.7f, false) == 0);
  CHECK(dshot::value_from_command(0.0f, true) == 48);
  CHECK(dshot::value_from_command(-1.0f, true) == 48);
  CHECK(dshot::value_from_command(std::numeric_limits<float>::quiet_NaN(), true) == 48);
  CHECK(dshot::value_from_command(1.0f, true) == 2047);
  CHECK(dshot::value_from_command(5.0f, true) == 2047);
  CHECK(dshot::value_from_command(std::numeric_limits<float>::infinity(), true) == 2047);
  CHECK(dshot::value_from_command(0.5f, true) == 48 + 1000);  // 0.5 * 1999 = 999.5 -> 1000
}

TEST_CASE("dshot600 bit timings in ticks of the 84 MHz timer clock") {
  // 84 MHz / 600 kbit/s = 140 ticks (1.667 us); T1H = 3/4 = 105 ticks (1.25 us);
  // T0H = 3/8 = 52.5 -> 53 ticks (0.631 us, the specification's 0.625 us).
  const dshot::BitTiming t = dshot::bit_timing(84000000, dshot::kDshot600BitRate);
  CHECK(t.valid);
  CHECK(t.period_ticks == 140);
  CHECK(t.t1h_ticks == 105);
  CHECK(t.t0h_ticks == 53);
  CHECK(fw::drivers::omnibus_f4::kDshot600.period_ticks == 140);

  // The HSI-only fallback clock (16 MHz timers): 26.67 -> 27 ticks is 1.2 % slow, still valid.
  const dshot::BitTiming slow = dshot::bit_timing(16000000, dshot::kDshot600BitRate);
  CHECK(slow.valid);
  CHECK(slow.period_ticks == 27);
  CHECK(slow.t0h_ticks == 10);
  CHECK(slow.t1h_ticks == 20);

  // Too slow a clock cannot make the bits.
  CHECK_FALSE(dshot::bit_timing(3000000, dshot::kDshot600BitRate).valid);
  CHECK_FALSE(dshot::bit_timing(0, dshot::kDshot600BitRate).valid);
  CHECK_FALSE(dshot::bit_timing(84000000, 0).valid);
}

TEST_CASE("pulses follow the frame's bits, most significant first, then hold the line low") {
  const dshot::BitTiming t = dshot::bit_timing(84000000, dshot::kDshot600BitRate);
  const dshot::Pulses p = dshot::pulses(0x82C6, t);  // 1000 0010 1100 0110
  const int bits[16] = {1, 0, 0, 0, 0, 0, 1, 0, 1, 1, 0, 0, 0, 1, 1, 0};
  for (int i = 0; i < 16; ++i) CHECK(p[i] == (bits[i] ? 105u : 53u));
  CHECK(p[16] == 0);
  CHECK(p[17] == 0);
}
