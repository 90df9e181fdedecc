// The few STM32F405 and Cortex-M4 registers this port uses, from ST's RM0090 (STM32F405/415
// reference manual) and Arm's ARMv7-M Architecture Reference Manual. Debian packages neither
// CMSIS nor libopencm3, so they are written out here; every layout is checked against the
// manual's offsets with static_assert.
#pragma once

#include <cstddef>
#include <cstdint>

namespace stm32f4 {

using Reg = volatile std::uint32_t;

template <class T>
inline T& at(std::uintptr_t address) {
  return *reinterpret_cast<T*>(address);
}

// ---------------------------------------------------------------------------------------
// Reset and clock control (RM0090 section 7.3)
// ---------------------------------------------------------------------------------------
struct Rcc {
  Reg CR, PLLCFGR, CFGR, CIR, AHB1RSTR, AHB2RSTR, AHB3RSTR, reserved0, APB1RSTR, APB2RSTR;
  Reg reserved1[2];
  Reg AHB1ENR, AHB2ENR, AHB3ENR, reserved2, APB1ENR, APB2ENR;
};
static_assert(offsetof(Rcc, APB1RSTR) == 0x20 && offsetof(Rcc, AHB1ENR) == 0x30 &&
              offsetof(Rcc, APB1ENR) == 0x40);
inline Rcc& rcc() { return at<Rcc>(0x40023800u); }

namespace rcc_bits {
inline constexpr std::uint32_t cr_hsion = 1u << 0, cr_hsirdy = 1u << 1, cr_hseon = 1u << 16,
                               cr_hserdy = 1u << 17, cr_hsebyp = 1u << 18, cr_csson = 1u << 19,
                               cr_pllon = 1u << 24, cr_pllrdy = 1u << 25;
inline constexpr std::uint32_t pllcfgr_src_hse = 1u << 22;
inline constexpr std::uint32_t cfgr_sw_mask = 3u << 0, cfgr_sw_hsi = 0u, cfgr_sw_pll = 2u;
inline constexpr std::uint32_t cfgr_sws_mask = 3u << 2, cfgr_sws_pll = 2u << 2;
inline constexpr std::uint32_t cfgr_hpre_mask = 0xFu << 4;  // AHB /1 when 0
inline constexpr std::uint32_t cfgr_ppre1_mask = 7u << 10, cfgr_ppre1_div4 = 5u << 10;
inline constexpr std::uint32_t cfgr_ppre2_mask = 7u << 13, cfgr_ppre2_div2 = 4u << 13;
inline constexpr std::uint32_t ahb1_gpioa = 1u << 0, ahb1_gpiob = 1u << 1, ahb1_gpiod = 1u << 3;
inline constexpr std::uint32_t apb1_tim2 = 1u << 0, apb1_can1 = 1u << 25, apb1_pwr = 1u << 28;
}  // namespace rcc_bits

// Embedded flash interface (RM0090 section 3.9)
struct Flash {
  Reg ACR;
};
inline Flash& flash() { return at<Flash>(0x40023C00u); }
namespace flash_bits {
inline constexpr std::uint32_t acr_latency_mask = 7u, acr_prften = 1u << 8, acr_icen = 1u << 9,
                               acr_dcen = 1u << 10;
}

// Power controller (RM0090 section 5.4)
struct Pwr {
  Reg CR, CSR;
};
inline Pwr& pwr() { return at<Pwr>(0x40007000u); }
namespace pwr_bits {
inline constexpr std::uint32_t cr_vos_scale1 = 1u << 14;  // needed for 168 MHz
}

// ---------------------------------------------------------------------------------------
// GPIO (RM0090 section 8.4)
// ---------------------------------------------------------------------------------------
struct Gpio {
  Reg MODER, OTYPER, OSPEEDR, PUPDR, IDR, ODR, BSRR, LCKR, AFRL, AFRH;
};
static_assert(offsetof(Gpio, AFRH) == 0x24);
inline Gpio& gpiob() { return at<Gpio>(0x40020400u); }

// ---------------------------------------------------------------------------------------
// General-purpose timer TIM2, 32 bits (RM0090 section 18.4)
// ---------------------------------------------------------------------------------------
struct Tim {
  Reg CR1, CR2, SMCR, DIER, SR, EGR, CCMR1, CCMR2, CCER, CNT, PSC, ARR;
};
static_assert(offsetof(Tim, CNT) == 0x24 && offsetof(Tim, ARR) == 0x2C);
inline Tim& tim2() { return at<Tim>(0x40000000u); }

// ---------------------------------------------------------------------------------------
// bxCAN (RM0090 section 32.9)
// ---------------------------------------------------------------------------------------
struct CanTxMailbox {
  Reg TIR, TDTR, TDLR, TDHR;
};
struct CanRxFifo {
  Reg RIR, RDTR, RDLR, RDHR;
};
struct CanFilterBank {
  Reg FR1, FR2;
};
struct Can {
  Reg MCR, MSR, TSR, RF0R, RF1R, IER, ESR, BTR;
  Reg reserved0[88];
  CanTxMailbox tx[3];
  CanRxFifo rx[2];
  Reg reserved1[12];
  Reg FMR, FM1R, reserved2, FS1R, reserved3, FFA1R, reserved4, FA1R;
  Reg reserved5[8];
  CanFilterBank filter[28];
};
static_assert(offsetof(Can, BTR) == 0x1C && offsetof(Can, tx) == 0x180 && offsetof(Can, rx) == 0x1B0 &&
              offsetof(Can, FMR) == 0x200 && offsetof(Can, FA1R) == 0x21C && offsetof(Can, filter) == 0x240);
inline Can& can1() { return at<Can>(0x40006400u); }

namespace can_bits {
inline constexpr std::uint32_t mcr_inrq = 1u << 0, mcr_sleep = 1u << 1, mcr_txfp = 1u << 2,
                               mcr_rflm = 1u << 3, mcr_nart = 1u << 4, mcr_awum = 1u << 5, mcr_abom = 1u << 6,
                               mcr_reset = 1u << 15;
inline constexpr std::uint32_t msr_inak = 1u << 0, msr_slak = 1u << 1, msr_erri = 1u << 2;
inline constexpr std::uint32_t tsr_rqcp0 = 1u << 0, tsr_txok0 = 1u << 1, tsr_alst0 = 1u << 2,
                               tsr_terr0 = 1u << 3;
inline constexpr std::uint32_t tsr_mailbox_stride = 8;  // RQCP1 is bit 8, RQCP2 bit 16
inline constexpr std::uint32_t tsr_tme0 = 1u << 26;     // TME1, TME2 follow
inline constexpr std::uint32_t rfr_fmp_mask = 3u, rfr_full = 1u << 3, rfr_fovr = 1u << 4, rfr_rfom = 1u << 5;
inline constexpr std::uint32_t ier_tmeie = 1u << 0, ier_fmpie0 = 1u << 1, ier_fovie0 = 1u << 3,
                               ier_ewgie = 1u << 8, ier_epvie = 1u << 9, ier_bofie = 1u << 10,
                               ier_errie = 1u << 15;
inline constexpr std::uint32_t esr_ewgf = 1u << 0, esr_epvf = 1u << 1, esr_boff = 1u << 2;
inline constexpr std::uint32_t esr_lec_shift = 4, esr_lec_mask = 7u << 4, esr_tec_shift = 16,
                               esr_rec_shift = 24;
inline constexpr std::uint32_t ir_txrq = 1u << 0, ir_rtr = 1u << 1, ir_ide = 1u << 2, ir_stid_shift = 21;
inline constexpr std::uint32_t fmr_finit = 1u << 0;
}  // namespace can_bits

// ---------------------------------------------------------------------------------------
// Cortex-M4 core peripherals (ARMv7-M ARM, chapter B3)
// ---------------------------------------------------------------------------------------
struct Scb {
  Reg CPUID, ICSR, VTOR, AIRCR, SCR, CCR;
};
inline Scb& scb() { return at<Scb>(0xE000ED00u); }
inline Reg& cpacr() { return at<Reg>(0xE000ED88u); }
inline Reg& demcr() { return at<Reg>(0xE000EDFCu); }
inline constexpr std::uint32_t demcr_trcena = 1u << 24;

struct Dwt {
  Reg CTRL, CYCCNT;
};
inline Dwt& dwt() { return at<Dwt>(0xE0001000u); }
inline Reg& dwt_lar() { return at<Reg>(0xE0001FB0u); }  // lock access; unlocked with 0xC5ACCE55
inline constexpr std::uint32_t dwt_ctrl_cyccntena = 1u << 0;

struct Nvic {
  Reg ISER[8];
  Reg reserved0[24];
  Reg ICER[8];
  Reg reserved1[24];
  Reg ISPR[8];
  Reg reserved2[24];
  Reg ICPR[8];
};
static_assert(offsetof(Nvic, ICER) == 0x80 && offsetof(Nvic, ISPR) == 0x100 && offsetof(Nvic, ICPR) == 0x180);
inline Nvic& nvic() { return at<Nvic>(0xE000E100u); }
inline volatile std::uint8_t& nvic_priority(unsigned irq) {
  return at<volatile std::uint8_t>(0xE000E400u + irq);
}

// STM32F405 interrupt numbers (RM0090 table 61) used by this port.
namespace irq {
inline constexpr unsigned can1_tx = 19, can1_rx0 = 20, can1_rx1 = 21, can1_sce = 22;
inline constexpr unsigned count = 82;  // WWDG (0) .. FPU (81)
}  // namespace irq

inline void nvic_enable(unsigned irq, std::uint8_t priority) {
  nvic_priority(irq) = static_cast<std::uint8_t>(priority << 4);  // 4 priority bits, in the top nibble
  nvic().ICPR[irq / 32] = 1u << (irq % 32);
  nvic().ISER[irq / 32] = 1u << (irq % 32);
}
inline void nvic_set_pending(unsigned irq) { nvic().ISPR[irq / 32] = 1u << (irq % 32); }

// Interrupt masking for short critical sections: the previous state is restored, so these nest.
inline std::uint32_t irq_save() {
  std::uint32_t primask;
  asm volatile("mrs %0, primask\n\tcpsid i" : "=r"(primask)::"memory");
  return primask;
}
inline void irq_restore(std::uint32_t primask) { asm volatile("msr primask, %0" ::"r"(primask) : "memory"); }

}  // namespace stm32f4
