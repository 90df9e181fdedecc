// Standard ESC PWM on the four motor pads (motor_output.hpp): TIM3 and TIM2 count microseconds
// (fw/drivers/pwm.hpp) with a 490 Hz period, channels 3-4 in PWM mode 1 with preload, so a
// new width takes effect at the next period and never cuts a pulse short.
#include "fw/drivers/omnibus_f4.hpp"
#include "fw/drivers/pwm.hpp"
#include "motor_output.hpp"
#include "pins.hpp"
#include "registers.hpp"

namespace stm32f405 {
namespace {

using namespace stm32f4;
namespace board = fw::drivers::omnibus_f4;
namespace pwm = fw::drivers::pwm;

bool g_ready = false;
MotorOutputStats g_stats;

Tim& timer_of(const board::Motor& m) { return m.timer == 3 ? tim3() : tim2(); }

void configure_timer(Tim& tim, const pwm::Timing& t) {
  tim.CR1 = 0;
  tim.PSC = t.prescaler;
  tim.ARR = t.period_ticks - 1u;
  tim.CCR3 = pwm::kStopUs;
  tim.CCR4 = pwm::kStopUs;
  const std::uint32_t oc = (tim_bits::ccmr_pwm1 << 4) | tim_bits::ccmr_preload;
  tim.CCMR2 = oc | (oc << 8);
  tim.CCER = (1u << 8) | (1u << 12);  // CC3E, CC4E; active high
  tim.EGR = tim_bits::egr_ug;
  tim.CR1 = tim_bits::cr1_arpe | tim_bits::cr1_cen;
}

}  // namespace

const char* MotorOutput::name() { return "pwm_us"; }

bool MotorOutput::init(std::uint32_t timer_hz) {
  const pwm::Timing t = pwm::timing(timer_hz, pwm::kRateHz);
  if (!t.valid) return false;
  rcc().APB1ENR |= rcc_bits::apb1_tim2 | rcc_bits::apb1_tim3;
  (void)rcc().APB1ENR;
  configure_timer(tim3(), t);
  configure_timer(tim2(), t);
  for (const board::Motor& m : board::kMotors) configure_pin(m.pin, gpio_mode_af, Pull::down);
  g_ready = true;
  return true;
}

void MotorOutput::write(const fw::Motors& command, bool enabled) {
  if (!g_ready) return;
  for (std::size_t i = 0; i < 4; ++i) {
    const std::uint8_t pad = board::kMotorPad[i];
    const board::Motor& m = board::kMotors[pad];
    const std::uint16_t us = pwm::pulse_us(command[i], enabled);
    (m.channel == 3 ? timer_of(m).CCR3 : timer_of(m).CCR4) = us;
    g_stats.last_values[pad] = us;
  }
  ++g_stats.frames;
}

const MotorOutputStats& MotorOutput::stats() { return g_stats; }

}  // namespace stm32f405
