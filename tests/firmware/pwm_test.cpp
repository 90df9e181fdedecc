// Standard ESC PWM, the flight image's fallback motor output: pulse widths and timer set-up.
#include <catch2/catch.hpp>

#include <limits>

#include "fw/drivers/pwm.hpp"

namespace pwm = fw::drivers::pwm;

TEST_CASE("pwm pulses: 1000 us stop, 2000 us full, clamped") {
  CHECK(pwm::pulse_us(0.8f, false) == 1000);
  CHECK(pwm::pulse_us(0.0f, true) == 1000);
  CHECK(pwm::pulse_us(-3.0f, true) == 1000);
  CHECK(pwm::pulse_us(std::numeric_limits<float>::quiet_NaN(), true) == 1000);
  CHECK(pwm::pulse_us(0.25f, true) == 1250);
  CHECK(pwm::pulse_us(0.5f, true) == 1500);
  CHECK(pwm::pulse_us(1.0f, true) == 2000);
  CHECK(pwm::pulse_us(7.0f, true) == 2000);
}

TEST_CASE("pwm timing: 1 us ticks from the timer clock, 490 Hz period") {
  const pwm::Timing t = pwm::timing(84000000, pwm::kRateHz);  // TIM2/TIM3 at SYSCLK 168 MHz
  CHECK(t.valid);
  CHECK(t.prescaler == 83);
  CHECK(t.period_ticks == 2040);                                // 1e6 / 490 = 2040.8 -> 2040 us, 490.2 Hz
  const pwm::Timing hsi = pwm::timing(16000000, pwm::kRateHz);  // the HSI fallback
  CHECK(hsi.valid);
  CHECK(hsi.prescaler == 15);
  CHECK_FALSE(pwm::timing(16500000, pwm::kRateHz).valid);  // not a whole number of MHz
  CHECK_FALSE(pwm::timing(84000000, 600).valid);           // a 1667 us period cannot hold 2000 us
}
