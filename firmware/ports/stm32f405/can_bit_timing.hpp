// bxCAN bit timing: one bit = (1 + BS1 + BS2) time quanta of `prescaler` kernel-clock cycles.
// The sample point sits near 6/7 of the bit (BS1 11 / BS2 2 of 14 tq at 1 Mbit/s from
// APB1 = 42 MHz, prescaler 3), within CiA 301's recommended 85-90 %.
#pragma once

#include <cstdint>

namespace stm32f405 {

struct CanBitTiming {
  std::uint32_t prescaler = 0;  // 1..1024
  std::uint32_t bs1_tq = 0;     // 1..16
  std::uint32_t bs2_tq = 0;     // 1..8
  std::uint32_t sjw_tq = 1;     // 1..4
  bool valid = false;

  // The CAN_BTR value (every field is stored minus one).
  constexpr std::uint32_t btr() const {
    return ((sjw_tq - 1u) << 24) | ((bs2_tq - 1u) << 20) | ((bs1_tq - 1u) << 16) | (prescaler - 1u);
  }
};

// The longest bit (most quanta, 16 down to 8) that divides the kernel clock exactly;
// invalid when none does.
constexpr CanBitTiming can_bit_timing(std::uint32_t kernel_clock_hz, std::uint32_t bitrate) {
  CanBitTiming t;
  for (std::uint32_t tq = 16; tq >= 8; --tq) {
    const std::uint32_t quantum_hz = bitrate * tq;
    if (kernel_clock_hz % quantum_hz != 0u) continue;
    const std::uint32_t prescaler = kernel_clock_hz / quantum_hz;
    if (prescaler < 1u || prescaler > 1024u) continue;
    t.prescaler = prescaler;
    t.bs1_tq = (tq * 6u + 3u) / 7u - 1u;  // sample point at the quantum nearest 6/7
    t.bs2_tq = tq - 1u - t.bs1_tq;
    t.sjw_tq = 1;
    t.valid = t.bs1_tq >= 1u && t.bs1_tq <= 16u && t.bs2_tq >= 1u && t.bs2_tq <= 8u;
    if (t.valid) return t;
  }
  return CanBitTiming{};
}

inline constexpr CanBitTiming kCan1Mbit42MHz = can_bit_timing(42000000, 1000000);
static_assert(kCan1Mbit42MHz.valid && kCan1Mbit42MHz.prescaler == 3 && kCan1Mbit42MHz.bs1_tq == 11 &&
                  kCan1Mbit42MHz.bs2_tq == 2,
              "1 Mbit/s from APB1 = 42 MHz: prescaler 3, BS1 11, BS2 2");
static_assert(can_bit_timing(16000000, 1000000).valid, "the bare-HSI fallback still has a timing");

}  // namespace stm32f405
