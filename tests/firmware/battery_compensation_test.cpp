// The battery's compensation: the voltage validated, filtered and aged, the factor (V_ref / V)^2
// with its limits, the mixer allocating under the lowered ceiling, and the vehicle wiring it.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "fw/battery_compensation.hpp"
#include "fw/mixer.hpp"
#include "fw/vehicle.hpp"

namespace {

using fw::BatteryCompensation;

constexpr std::uint32_t kPeriod_us = 10000;  // HIL_BATTERY and the flight image's ADC: 100 Hz

fw::BatteryConfig config(float reference_V = 12.6f) {
  fw::BatteryConfig c{};
  c.reference_voltage_V = reference_V;
  return c;
}

// `n` readings of `mv`, one every 10 ms from `t_us`; returns the time after the last.
std::uint32_t feed(BatteryCompensation& b, std::uint16_t mv, int n, std::uint32_t t_us) {
  for (int i = 0; i < n; ++i, t_us += kPeriod_us) b.on_voltage_mv(mv, t_us);
  return t_us;
}

}  // namespace

TEST_CASE("without a voltage the factor is 1 and the compensation inactive") {
  BatteryCompensation b(config());
  CHECK(b.factor() == 1.0f);
  CHECK_FALSE(b.active());
  CHECK(b.filtered_mv() == 0);
  CHECK_FALSE(b.check_stale(1000000));
}

TEST_CASE("at the reference voltage the factor is exactly 1") {
  BatteryCompensation b(config());
  CHECK_FALSE(b.on_voltage_mv(12600, 0));  // the factor did not change
  CHECK(b.active());
  CHECK(b.factor() == 1.0f);
  CHECK(b.filtered_mv() == 12600);
  feed(b, 12600, 100, kPeriod_us);
  CHECK(b.factor() == 1.0f);
}

TEST_CASE("the factor is (V_ref / V)^2 of the filtered voltage") {
  BatteryCompensation b(config());
  REQUIRE(b.on_voltage_mv(11400, 0));  // the first reading starts the filter
  CHECK(b.factor() == Approx((12.6 / 11.4) * (12.6 / 11.4)).epsilon(1e-6));
  CHECK(b.filtered_mv() == 11400);
  // A 3S pack at half charge hovering (about 11.4 V): 1.22, within the limit.
  CHECK(b.factor() < BatteryCompensation::kFactorMax);
  // Above the reference (a freshly charged HV pack) the commands shrink.
  BatteryCompensation high(config());
  high.on_voltage_mv(13000, 0);
  CHECK(high.factor() == Approx((12.6 / 13.0) * (12.6 / 13.0)).epsilon(1e-6));
}

TEST_CASE("the voltage is low-pass filtered with a 0.1 s time constant") {
  BatteryCompensation b(config());
  std::uint32_t t = feed(b, 12000, 1, 0);
  // A step to 11.0 V: after one time constant (10 readings at 10 ms) 1 - (1 / 1.1)^10 of the step.
  t = feed(b, 11000, 10, t);
  const double expected_V = 12.0 - 1.0 * (1.0 - std::pow(0.1 / 0.11, 10));
  CHECK(b.filtered_mv() == Approx(expected_V * 1000.0).margin(1.0));
  // ... and it settles on the new voltage.
  feed(b, 11000, 200, t);
  CHECK(b.filtered_mv() == Approx(11000).margin(1));
  CHECK(b.factor() == Approx((12.6 / 11.0) * (12.6 / 11.0)).epsilon(1e-4));
}

TEST_CASE("a reading out of range is refused and counted") {
  BatteryCompensation b(config());
  CHECK_FALSE(b.on_voltage_mv(0, 0));      // no pack, or a disconnected divider
  CHECK_FALSE(b.on_voltage_mv(7500, 0));   // below 0.6 V_ref: a 2S pack, or a broken reading
  CHECK_FALSE(b.on_voltage_mv(14500, 0));  // above 1.15 V_ref: a 4S pack
  CHECK_FALSE(b.on_voltage_mv(65535, 0));
  CHECK(b.rejected() == 4);
  CHECK_FALSE(b.active());
  CHECK(b.factor() == 1.0f);
  // A valid reading later is used; a bad one among good ones leaves the filter alone.
  b.on_voltage_mv(11800, kPeriod_us);
  const float factor = b.factor();
  b.on_voltage_mv(0, 2 * kPeriod_us);
  CHECK(b.factor() == factor);
  CHECK(b.filtered_mv() == 11800);
  CHECK(b.rejected() == 5);
}

TEST_CASE("the factor stops at kFactorMax") {
  BatteryCompensation b(config());
  b.on_voltage_mv(8000, 0);  // valid (above 0.6 V_ref) but an empty pack under load
  CHECK(b.factor() == BatteryCompensation::kFactorMax);
}

TEST_CASE("a voltage that stops coming goes stale: factor 1") {
  BatteryCompensation b(config());
  std::uint32_t t = feed(b, 11000, 5, 0);
  const std::uint32_t last = t - kPeriod_us;
  CHECK(b.factor() > 1.0f);
  CHECK_FALSE(b.check_stale(last + BatteryCompensation::kStale_us));
  CHECK(b.active());
  CHECK(b.check_stale(last + BatteryCompensation::kStale_us + 1));
  CHECK_FALSE(b.active());
  CHECK(b.factor() == 1.0f);
  CHECK(b.filtered_mv() == 0);
  // The next reading restarts the filter from itself (not from the old value).
  t = last + 2 * BatteryCompensation::kStale_us;
  b.on_voltage_mv(12000, t);
  CHECK(b.filtered_mv() == 12000);
  // A gap longer than kDtMax_s restarts it too.
  b.on_voltage_mv(11000, t + 200000);
  CHECK(b.filtered_mv() == 11000);
}

TEST_CASE("the clock wrapping does not disturb the filter") {
  BatteryCompensation b(config());
  const std::uint32_t t0 = 0xFFFFFFFFu - 5000u;
  b.on_voltage_mv(12000, t0);
  b.on_voltage_mv(11000, t0 + kPeriod_us);  // wraps past zero
  CHECK(b.filtered_mv() == Approx(12000 - 1000 * (0.01 / 0.11)).margin(1));
  CHECK_FALSE(b.check_stale(t0 + kPeriod_us + 1000));
}

TEST_CASE("no reference voltage, or a broken one, turns the compensation off") {
  for (const float v_ref : {0.0f, -12.6f, std::numeric_limits<float>::quiet_NaN(),
                            std::numeric_limits<float>::infinity(), 200.0f}) {
    BatteryCompensation b(config(v_ref));
    CHECK_FALSE(b.on_voltage_mv(12600, 0));
    CHECK_FALSE(b.active());
    CHECK(b.factor() == 1.0f);
  }
}

TEST_CASE("the mixer allocates under the ceiling the battery leaves, attitude first") {
  const fw::AirframeConfig airframe{};
  fw::Mixer m(airframe);
  const fw::MixerInput hover{0.52f * 9.81f, {0.0f, 0.0f, 0.0f}};
  const fw::MixerOutput before = m.mix(hover);
  // Factor 1: exactly the allocation without compensation.
  REQUIRE(m.set_command_factor(1.0f));
  const fw::MixerOutput same = m.mix(hover);
  for (int i = 0; i < 4; ++i) CHECK(same.command[i] == before.command[i]);

  // At factor 1.3 each command is 1.3 times the thrust fraction at V_ref, the thrusts the same.
  REQUIRE(m.set_command_factor(1.3f));
  const fw::MixerOutput compensated = m.mix(hover);
  for (int i = 0; i < 4; ++i) {
    CHECK(compensated.thrust_N[i] == Approx(before.thrust_N[i]));
    CHECK(compensated.command[i] == Approx(1.3f * before.command[i]).epsilon(1e-6));
  }
  CHECK(compensated.saturation == 0);

  // Near full thrust with a roll torque: the collective gives way, the roll torque is kept whole
  // and no command exceeds 1.
  const fw::MixerInput climb_and_roll{4.0f * airframe.motor_thrust_max_N * 0.95f, {0.05f, 0.0f, 0.0f}};
  const fw::MixerOutput sat = m.mix(climb_and_roll);
  CHECK((sat.saturation & fw::saturation::collective_high) != 0);
  CHECK((sat.saturation & (fw::saturation::roll_pos | fw::saturation::roll_neg)) == 0);
  CHECK(sat.torque_unallocated_Nm[0] == Approx(0.0f).margin(1e-5));
  for (int i = 0; i < 4; ++i) {
    CHECK(sat.command[i] <= 1.0f);
    CHECK(sat.thrust_N[i] <= airframe.motor_thrust_max_N / 1.3f + 1e-5f);
  }
  CHECK(*std::max_element(sat.command.begin(), sat.command.end()) == Approx(1.0f));

  // Refused: the previous factor stays.
  CHECK_FALSE(m.set_command_factor(0.0f));
  CHECK_FALSE(m.set_command_factor(std::numeric_limits<float>::quiet_NaN()));
  CHECK_FALSE(m.set_command_factor(airframe.motor_thrust_max_N / airframe.motor_thrust_min_N));
  CHECK(m.thrust_ceiling_N() == Approx(airframe.motor_thrust_max_N / 1.3f));
}

TEST_CASE("the vehicle compensates from the voltage its port notes and reports it") {
  fw::VehicleConfig c{};
  fw::Vehicle v(c);
  CHECK(v.battery().factor() == 1.0f);
  v.note_battery_mv(11400);
  CHECK(v.battery().active());
  CHECK(v.battery().factor() == Approx((12.6 / 11.4) * (12.6 / 11.4)).epsilon(1e-6));
  CHECK(v.battery().filtered_mv() == 11400);
}
