#include "clock.hpp"

#include "cycle_counter.hpp"
#include "registers.hpp"

namespace stm32f405 {
namespace {

using namespace stm32f4;

constexpr std::uint32_t kHseHz = 8000000;
constexpr std::uint32_t kHsiHz = 16000000;
constexpr std::uint32_t kSysclkHz = 168000000;

// PLL: f_vco = f_in / M * N (the input after /M should be 2 MHz to keep jitter low),
// SYSCLK = f_vco / P, USB/SDIO = f_vco / Q = 48 MHz.
constexpr std::uint32_t kPllN = 168, kPllP = 2, kPllQ = 7;
constexpr std::uint32_t pll_m(std::uint32_t input_hz) { return input_hz / 2000000u; }
static_assert(kHseHz / pll_m(kHseHz) * kPllN / kPllP == kSysclkHz);
static_assert(kHsiHz / pll_m(kHsiHz) * kPllN / kPllP == kSysclkHz);
static_assert(kHseHz / pll_m(kHseHz) * kPllN / kPllQ == 48000000);

// Timeouts in cycles of the reset clock (HSI, 16 MHz). ST's reference code allows the
// crystal 100 ms; the PLL locks in well under 1 ms.
constexpr std::uint32_t kHseTimeoutCycles = kHsiHz / 10;      // 100 ms
constexpr std::uint32_t kPllTimeoutCycles = kHsiHz / 100;     // 10 ms
constexpr std::uint32_t kSwitchTimeoutCycles = kHsiHz / 100;  // 10 ms

// The PLL fields of RCC_PLLCFGR; the other bits are reserved and keep their reset values.
constexpr std::uint32_t kPllcfgrFields =
    0x3Fu | (0x1FFu << 6) | (3u << 16) | rcc_bits::pllcfgr_src_hse | (0xFu << 24);

std::uint32_t pllcfgr(std::uint32_t current, bool from_hse) {
  const std::uint32_t m = pll_m(from_hse ? kHseHz : kHsiHz);
  return (current & ~kPllcfgrFields) | m | (kPllN << 6) | (((kPllP / 2u) - 1u) << 16) |
         (from_hse ? rcc_bits::pllcfgr_src_hse : 0u) | (kPllQ << 24);
}

}  // namespace

ClockReport clock_init() {
  ClockReport report;
  Rcc& r = rcc();

  // Make sure we run from the HSI with the PLL off, whatever a bootloader left behind.
  r.CR |= rcc_bits::cr_hsion;
  wait_for(r.CR, rcc_bits::cr_hsirdy, rcc_bits::cr_hsirdy, kSwitchTimeoutCycles);
  r.CFGR = (r.CFGR & ~rcc_bits::cfgr_sw_mask) | rcc_bits::cfgr_sw_hsi;
  wait_for(r.CFGR, rcc_bits::cfgr_sws_mask, 0u, kSwitchTimeoutCycles);
  r.CR &= ~rcc_bits::cr_pllon;

  // The crystal: an oscillator, not an external clock (HSEBYP off).
  r.CR = (r.CR & ~rcc_bits::cr_hsebyp) | rcc_bits::cr_hseon;
  const bool hse_ok = wait_for(r.CR, rcc_bits::cr_hserdy, rcc_bits::cr_hserdy, kHseTimeoutCycles);
  if (!hse_ok) {
    r.CR &= ~rcc_bits::cr_hseon;
    report.hse_failed = true;
  }

  // 168 MHz needs voltage scale 1 and 5 flash wait states (RM0090 table 10, 2.7-3.6 V),
  // set before the clock goes up; the ACR is read back because the new latency must be in
  // force before the switch.
  r.APB1ENR |= rcc_bits::apb1_pwr;
  (void)r.APB1ENR;  // the enable takes effect after a read-back
  pwr().CR |= pwr_bits::cr_vos_scale1;
  flash().ACR = 5u | flash_bits::acr_prften | flash_bits::acr_icen | flash_bits::acr_dcen;
  const bool flash_ok = (flash().ACR & flash_bits::acr_latency_mask) == 5u;

  // AHB /1, APB1 /4 (42 MHz, its maximum), APB2 /2 (84 MHz, its maximum).
  r.CFGR = (r.CFGR & ~(rcc_bits::cfgr_hpre_mask | rcc_bits::cfgr_ppre1_mask | rcc_bits::cfgr_ppre2_mask)) |
           rcc_bits::cfgr_ppre1_div4 | rcc_bits::cfgr_ppre2_div2;

  r.PLLCFGR = pllcfgr(r.PLLCFGR, hse_ok);
  r.CR |= rcc_bits::cr_pllon;
  bool pll_ok = flash_ok && wait_for(r.CR, rcc_bits::cr_pllrdy, rcc_bits::cr_pllrdy, kPllTimeoutCycles);
  if (pll_ok) {
    r.CFGR = (r.CFGR & ~rcc_bits::cfgr_sw_mask) | rcc_bits::cfgr_sw_pll;
    pll_ok = wait_for(r.CFGR, rcc_bits::cfgr_sws_mask, rcc_bits::cfgr_sws_pll, kSwitchTimeoutCycles);
  }

  if (pll_ok) {
    report.source = hse_ok ? ClockSource::hse_pll : ClockSource::hsi_pll;
    report.sysclk_hz = kSysclkHz;
    report.apb1_hz = kSysclkHz / 4u;
    report.apb2_hz = kSysclkHz / 2u;
    report.apb1_timer_hz = 2u * report.apb1_hz;
    return report;
  }

  // No PLL: stay on the bare HSI with undivided buses.
  report.pll_failed = true;
  r.CFGR = (r.CFGR & ~rcc_bits::cfgr_sw_mask) | rcc_bits::cfgr_sw_hsi;
  wait_for(r.CFGR, rcc_bits::cfgr_sws_mask, 0u, kSwitchTimeoutCycles);
  r.CR &= ~rcc_bits::cr_pllon;
  r.CFGR &= ~(rcc_bits::cfgr_ppre1_mask | rcc_bits::cfgr_ppre2_mask);
  report.source = ClockSource::hsi;
  report.sysclk_hz = kHsiHz;
  report.apb1_hz = kHsiHz;
  report.apb2_hz = kHsiHz;
  report.apb1_timer_hz = kHsiHz;
  return report;
}

}  // namespace stm32f405
