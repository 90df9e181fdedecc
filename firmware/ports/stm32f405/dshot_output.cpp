#include "motor_output.hpp"

#include "fw/drivers/dshot.hpp"
#include "fw/drivers/omnibus_f4.hpp"
#include "pins.hpp"
#include "registers.hpp"

namespace stm32f405 {
namespace {

using namespace stm32f4;
namespace board = fw::drivers::omnibus_f4;
namespace dshot = fw::drivers::dshot;

// One DMA stream per timer: TIM3_UP on DMA1 stream 2 channel 5, TIM2_UP on stream 1 channel 3.
struct TimerDma {
  std::uintptr_t timer_base;
  std::uint8_t stream;
  std::uint8_t channel;
};
constexpr TimerDma kTim3{kTim3Base, 2, 5};
constexpr TimerDma kTim2{kTim2Base, 1, 3};

// Per timer, each slot's CCR3 then CCR4 (the DMA burst writes them in register order).
using Burst = std::array<std::uint32_t, 2 * dshot::kSlotsPerFrame>;
Burst g_tim3_burst{};
Burst g_tim2_burst{};
dshot::BitTiming g_timing{};
bool g_ready = false;
MotorOutputStats g_stats;

Tim& timer(const TimerDma& t) { return at<Tim>(t.timer_base); }

void configure_timer(const TimerDma& t, std::uint32_t period_ticks) {
  Tim& tim = timer(t);
  tim.CR1 = 0;
  tim.PSC = 0;
  tim.ARR = period_ticks - 1u;
  tim.CCR3 = 0;  // line low between frames
  tim.CCR4 = 0;
  // PWM mode 1 with preload on channels 3 and 4: a compare value written during one bit takes
  // effect at the next update, so each DMA burst sets up the following bit.
  const std::uint32_t oc = (tim_bits::ccmr_pwm1 << 4) | tim_bits::ccmr_preload;
  tim.CCMR2 = oc | (oc << 8);
  tim.CCER = (1u << 8) | (1u << 12);  // CC3E, CC4E; active high
  // Burst of two transfers (DBL = 1) starting at CCR3 (offset 0x3C: DBA = 15).
  tim.DCR = (1u << 8) | (0x3Cu / 4u);
  tim.DIER = tim_bits::dier_ude;
  tim.EGR = tim_bits::egr_ug;
  tim.CR1 = tim_bits::cr1_arpe | tim_bits::cr1_cen;
}

std::uint32_t flag_shift(std::uint8_t stream) { return dma_bits::kFlagOffset[stream % 4u]; }

bool busy(const TimerDma& t) { return (dma1().stream[t.stream].CR & dma_bits::cr_en) != 0u; }

// Starts one timer's frame (its stream is idle).
void start(const TimerDma& t, const Burst& burst) {
  DmaStream& s = dma1().stream[t.stream];
  const std::uint32_t shift = flag_shift(t.stream);
  Reg& isr = t.stream < 4 ? dma1().LISR : dma1().HISR;
  Reg& ifcr = t.stream < 4 ? dma1().LIFCR : dma1().HIFCR;
  if ((isr & (dma_bits::flag_teif << shift)) != 0u) ++g_stats.dma_errors;
  ifcr = dma_bits::flags_all << shift;
  s.PAR = static_cast<std::uint32_t>(reinterpret_cast<std::uintptr_t>(&timer(t).DMAR));
  s.M0AR = static_cast<std::uint32_t>(reinterpret_cast<std::uintptr_t>(burst.data()));
  s.NDTR = static_cast<std::uint32_t>(burst.size());
  s.FCR = 0;  // direct mode
  s.CR = (static_cast<std::uint32_t>(t.channel) << dma_bits::cr_chsel_shift) | dma_bits::cr_pl_high |
         dma_bits::cr_msize_word | dma_bits::cr_psize_word | dma_bits::cr_minc |
         dma_bits::cr_dir_mem_to_periph | dma_bits::cr_en;
}

}  // namespace

const char* MotorOutput::name() { return "dshot"; }

bool MotorOutput::init(std::uint32_t timer_hz) {
  g_timing = dshot::bit_timing(timer_hz, dshot::kDshot600BitRate);
  if (!g_timing.valid) return false;
  rcc().AHB1ENR |= rcc_bits::ahb1_dma1;
  rcc().APB1ENR |= rcc_bits::apb1_tim2 | rcc_bits::apb1_tim3;
  (void)rcc().APB1ENR;
  configure_timer(kTim3, g_timing.period_ticks);
  configure_timer(kTim2, g_timing.period_ticks);
  for (const board::Motor& m : board::kMotors) configure_pin(m.pin, gpio_mode_af, Pull::down);
  g_ready = true;
  return true;
}

void MotorOutput::write(const fw::Motors& command, bool enabled) {
  if (!g_ready) return;
  std::array<std::uint16_t, 4> pad_values{};
  for (std::size_t i = 0; i < 4; ++i)
    pad_values[board::kMotorPad[i]] = dshot::value_from_command(command[i], enabled);
  // The buffers are not touched while a stream may still be reading them.
  if (busy(kTim3) || busy(kTim2)) {
    ++g_stats.skipped;
    return;
  }
  for (std::size_t pad = 0; pad < 4; ++pad) {
    const board::Motor& m = board::kMotors[pad];
    const dshot::Pulses p = dshot::pulses(dshot::frame(pad_values[pad], false), g_timing);
    Burst& burst = m.timer == 3 ? g_tim3_burst : g_tim2_burst;
    const std::size_t lane = m.channel == 3 ? 0u : 1u;
    for (std::size_t slot = 0; slot < dshot::kSlotsPerFrame; ++slot) burst[2 * slot + lane] = p[slot];
  }
  g_stats.last_values = pad_values;
  start(kTim3, g_tim3_burst);
  start(kTim2, g_tim2_burst);
  ++g_stats.frames;
}

const MotorOutputStats& MotorOutput::stats() { return g_stats; }

}  // namespace stm32f405
