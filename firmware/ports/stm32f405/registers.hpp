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
inline constexpr std::uint32_t ahb1_gpioa = 1u << 0, ahb1_gpiob = 1u << 1, ahb1_gpioc = 1u << 2,
                               ahb1_gpiod = 1u << 3, ahb1_dma1 = 1u << 21;
inline constexpr std::uint32_t apb1_tim2 = 1u << 0, apb1_tim3 = 1u << 1, apb1_tim5 = 1u << 3,
                               apb1_usart3 = 1u << 18, apb1_can1 = 1u << 25, apb1_pwr = 1u << 28;
inline constexpr std::uint32_t apb2_usart1 = 1u << 4, apb2_adc1 = 1u << 8, apb2_spi1 = 1u << 12,
                               apb2_syscfg = 1u << 14;
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
inline Gpio& gpioa() { return at<Gpio>(0x40020000u); }
inline Gpio& gpiob() { return at<Gpio>(0x40020400u); }
inline Gpio& gpioc() { return at<Gpio>(0x40020800u); }
inline Gpio& gpio(char port) { return port == 'A' ? gpioa() : port == 'B' ? gpiob() : gpioc(); }
inline constexpr std::uint32_t gpio_mode_output = 1u, gpio_mode_af = 2u, gpio_mode_analog = 3u;

// ---------------------------------------------------------------------------------------
// General-purpose timers TIM2..TIM5 (RM0090 section 18.4; TIM2 and TIM5 are 32 bits wide)
// ---------------------------------------------------------------------------------------
struct Tim {
  Reg CR1, CR2, SMCR, DIER, SR, EGR, CCMR1, CCMR2, CCER, CNT, PSC, ARR, RCR, CCR1, CCR2, CCR3, CCR4, BDTR,
      DCR, DMAR;
};
static_assert(offsetof(Tim, CNT) == 0x24 && offsetof(Tim, ARR) == 0x2C && offsetof(Tim, CCR3) == 0x3C &&
              offsetof(Tim, DCR) == 0x48 && offsetof(Tim, DMAR) == 0x4C);
inline constexpr std::uintptr_t kTim2Base = 0x40000000u, kTim3Base = 0x40000400u, kTim5Base = 0x40000C00u;
inline Tim& tim2() { return at<Tim>(kTim2Base); }
inline Tim& tim3() { return at<Tim>(kTim3Base); }
inline Tim& tim5() { return at<Tim>(kTim5Base); }
namespace tim_bits {
inline constexpr std::uint32_t cr1_cen = 1u << 0, cr1_arpe = 1u << 7, dier_ude = 1u << 8, egr_ug = 1u << 0;
inline constexpr std::uint32_t ccmr_pwm1 = 6u, ccmr_preload = 1u << 3;  // OCxM and OCxPE of one channel
}  // namespace tim_bits

// ---------------------------------------------------------------------------------------
// DMA controller (RM0090 section 10.5)
// ---------------------------------------------------------------------------------------
struct DmaStream {
  Reg CR, NDTR, PAR, M0AR, M1AR, FCR;
};
struct Dma {
  Reg LISR, HISR, LIFCR, HIFCR;
  DmaStream stream[8];
};
static_assert(offsetof(Dma, stream) == 0x10 && sizeof(DmaStream) == 0x18);
inline Dma& dma1() { return at<Dma>(0x40026000u); }
namespace dma_bits {
inline constexpr std::uint32_t cr_en = 1u << 0, cr_dir_mem_to_periph = 1u << 6, cr_minc = 1u << 10,
                               cr_psize_word = 2u << 11, cr_msize_word = 2u << 13, cr_pl_high = 2u << 16,
                               cr_chsel_shift = 25;
// A stream's five flags (FEIF, DMEIF, TEIF, HTIF, TCIF) in LISR/HISR and LIFCR/HIFCR: streams 0-3
// (4-7) at bit offsets 0, 6, 16, 22.
inline constexpr std::uint32_t kFlagOffset[4] = {0, 6, 16, 22};
inline constexpr std::uint32_t flags_all = 0x3Du, flag_teif = 1u << 3, flag_tcif = 1u << 5;
}  // namespace dma_bits

// ---------------------------------------------------------------------------------------
// SPI (RM0090 section 28.5), EXTI (12.3), SYSCFG (9.2), USART (30.6), ADC (13.13)
// ---------------------------------------------------------------------------------------
struct Spi {
  Reg CR1, CR2, SR, DR;
};
inline Spi& spi1() { return at<Spi>(0x40013000u); }
namespace spi_bits {
inline constexpr std::uint32_t cr1_cpha = 1u << 0, cr1_cpol = 1u << 1, cr1_mstr = 1u << 2, cr1_br_shift = 3,
                               cr1_spe = 1u << 6, cr1_ssi = 1u << 8, cr1_ssm = 1u << 9;
inline constexpr std::uint32_t cr2_rxneie = 1u << 6;
inline constexpr std::uint32_t sr_rxne = 1u << 0, sr_txe = 1u << 1, sr_bsy = 1u << 7;
}  // namespace spi_bits

struct Exti {
  Reg IMR, EMR, RTSR, FTSR, SWIER, PR;
};
inline Exti& exti() { return at<Exti>(0x40013C00u); }
struct Syscfg {
  Reg MEMRMP, PMC, EXTICR[4];
};
inline Syscfg& syscfg() { return at<Syscfg>(0x40013800u); }

struct Usart {
  Reg SR, DR, BRR, CR1, CR2, CR3, GTPR;
};
inline constexpr std::uintptr_t kUsart1Base = 0x40011000u, kUsart3Base = 0x40004800u;
namespace usart_bits {
inline constexpr std::uint32_t sr_ore = 1u << 3, sr_rxne = 1u << 5, sr_txe = 1u << 7;
inline constexpr std::uint32_t cr1_re = 1u << 2, cr1_te = 1u << 3, cr1_rxneie = 1u << 5, cr1_txeie = 1u << 7,
                               cr1_ue = 1u << 13;
}  // namespace usart_bits

struct Adc {
  Reg SR, CR1, CR2, SMPR1, SMPR2, JOFR[4], HTR, LTR, SQR1, SQR2, SQR3, JSQR, JDR[4], DR;
};
static_assert(offsetof(Adc, SQR3) == 0x34 && offsetof(Adc, DR) == 0x4C);
inline Adc& adc1() { return at<Adc>(0x40012000u); }
inline Reg& adc_common_ccr() { return at<Reg>(0x40012304u); }
namespace adc_bits {
inline constexpr std::uint32_t sr_eoc = 1u << 1, cr2_adon = 1u << 0, cr2_swstart = 1u << 30;
}

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

struct SysTick {
  Reg CSR, RVR, CVR, CALIB;
};
inline SysTick& systick() { return at<SysTick>(0xE000E010u); }
inline constexpr std::uint32_t systick_enable = 1u << 0, systick_tickint = 1u << 1,
                               systick_cpu_clock = 1u << 2;

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
inline constexpr unsigned exti4 = 10, can1_tx = 19, can1_rx0 = 20, can1_rx1 = 21, can1_sce = 22, spi1 = 35,
                          usart1 = 37, usart3 = 39;
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
