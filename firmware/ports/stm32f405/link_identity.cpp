#include "link_identity.hpp"

#include "cycle_counter.hpp"
#include "registers.hpp"

// The slot: erased flash (all ones) in the image; its own output section so that the flashing
// script can write a key into a copy of the image (objcopy --update-section .link_key=...).
extern "C" __attribute__((section(".link_key"), used)) const std::uint8_t pa_link_key[16] = {
    0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF};

namespace stm32f405 {

namespace {
// RM0090 section 24: the RNG, clocked by the PLL's 48 MHz output.
struct Rng {
  stm32f4::Reg CR, SR, DR;
};
inline Rng& rng() { return stm32f4::at<Rng>(0x50060800u); }
constexpr std::uint32_t kAhb2RngEn = 1u << 6;
constexpr std::uint32_t kCrRngEn = 1u << 2;
constexpr std::uint32_t kSrDataReady = 1u << 0, kSrClockError = 1u << 1, kSrSeedError = 1u << 2;
}  // namespace

bool load_link_identity(fw::LinkConfig& link, std::uint32_t sysclk_hz) {
  // Read through a volatile pointer: the compiler must not fold in the erased value it sees here.
  const volatile std::uint8_t* slot = pa_link_key;
  for (std::size_t i = 0; i < link.key.size(); ++i) link.key[i] = slot[i];

  stm32f4::rcc().AHB2ENR |= kAhb2RngEn;
  rng().CR = kCrRngEn;
  // A number takes 40 RNG clock periods; 1 ms is far more than enough.
  const bool ready = wait_for(rng().SR, kSrDataReady, kSrDataReady, sysclk_hz / 1000u) &&
                     (rng().SR & (kSrClockError | kSrSeedError)) == 0;
  if (!ready) {
    link.key = pa::auth::Key{};
    return false;
  }
  link.session_nonce = rng().DR;
  return true;
}

}  // namespace stm32f405
