// One vehicle's motor lag and rate-loop inertia on the ground (groundstation/runtime/motor_equaliser.hpp):
// what is set on board changes only when its SET_MOTOR_TIME_CONSTANT or SET_INERTIA_SCALE
// is acknowledged, a refused or lost one keeps the old, and each take-off's fit is kept as the
// latest identification.
#include <catch2/catch.hpp>

#include <algorithm>

#include "groundstation/runtime/motor_equaliser.hpp"

namespace {

using gs::estimation::IdentificationRefusal;
using gs::link::CommandHandle;
using gs::link::CommandState;
using gs::runtime::motor_lag_argument_us;
using gs::runtime::MotorEqualiser;

MotorEqualiser equaliser() { return MotorEqualiser(gs::runtime::IdentificationFlight{}, 0.03); }

}  // namespace

TEST_CASE("The command's argument is the lag in microseconds, rounded") {
  CHECK(motor_lag_argument_us(0.03) == 30000);
  CHECK(motor_lag_argument_us(0.0421234) == 42123);
  CHECK(motor_lag_argument_us(0.0421236) == 42124);
  CHECK(motor_lag_argument_us(0.0) == 0);
}

TEST_CASE("The design lag until a command is acknowledged; accepted, the lag sent") {
  MotorEqualiser e = equaliser();
  CHECK(e.equalised_s() == 0.03);
  CHECK_FALSE(e.lag().pending());
  e.lag().settle(CommandState::accepted);  // nothing in flight: nothing changes
  CHECK(e.equalised_s() == 0.03);
  e.lag().sent(0.045, CommandHandle{pa::kVehicle1, 7, 7});
  REQUIRE(e.lag().pending());
  CHECK(e.lag().pending()->serial == 7);
  e.lag().settle(CommandState::pending);
  CHECK(e.lag().pending());
  CHECK(e.equalised_s() == 0.03);
  e.lag().settle(CommandState::accepted);
  CHECK_FALSE(e.lag().pending());
  CHECK(e.equalised_s() == 0.045);
}

TEST_CASE("The inertia on board is the file's until SET_INERTIA_SCALE is acknowledged, in per mille") {
  CHECK(gs::runtime::inertia_scale_argument(0.8) == 800);
  CHECK(gs::runtime::inertia_scale_argument(1.0 / 1.17) == 855);
  MotorEqualiser e = equaliser();
  CHECK(e.inertia_scale() == 1.0);
  e.inertia().sent(0.8, CommandHandle{pa::kVehicle1, 3, 3});
  e.inertia().settle(CommandState::pending);
  CHECK(e.inertia_scale() == 1.0);
  e.inertia().settle(CommandState::accepted);
  CHECK(e.inertia_scale() == 0.8);
  CHECK(e.equalised_s() == 0.03);  // the lag untouched
  e.inertia().sent(0.7, CommandHandle{pa::kVehicle1, 4, 4});
  e.inertia().settle(CommandState::refused);
  CHECK(e.inertia_scale() == 0.8);
}

TEST_CASE("A refused or lost command keeps the lag on board") {
  for (CommandState failure : {CommandState::refused, CommandState::timed_out}) {
    MotorEqualiser e = equaliser();
    e.lag().sent(0.045, CommandHandle{pa::kVehicle1, 1, 1});
    e.lag().settle(failure);
    CHECK_FALSE(e.lag().pending());
    CHECK(e.equalised_s() == 0.03);
  }
}

TEST_CASE("The flight's fit is kept as the latest identification, and fitted against the lag on board") {
  MotorEqualiser e = equaliser();
  CHECK_FALSE(e.identified());
  CHECK_FALSE(e.finish(100.0));  // no flight
  e.start_identification(10.0);
  CHECK(e.flight().running());
  for (double t = 10.0; t < 11.5; t += 0.005) e.flight().command_sent(t, e.flight().excitation(t));
  std::optional<gs::estimation::IdentificationResult> result;
  for (int i = 0; i < 10 && !result; ++i) result = e.finish(12.0);
  REQUIRE(result);
  CHECK(result->refusal == IdentificationRefusal::no_telemetry);
  REQUIRE(e.identified());
  CHECK(e.identified()->refusal == IdentificationRefusal::no_telemetry);
  CHECK_FALSE(e.flight().running());
  CHECK_FALSE(e.finish(13.0));
  CHECK(e.identified());  // kept after the flight
}

namespace {

// Flies `e`'s running flight from `t0_s` to its fit with every rate report saturated or not.
std::optional<gs::estimation::IdentificationResult> fly(MotorEqualiser& e, double t0_s, bool saturated) {
  for (double t = t0_s; t < t0_s + 1.6; t += 0.005) {
    e.flight().command_sent(t, e.flight().excitation(t));
    e.flight().telemetry(t, e.flight().excitation(t), saturated);
  }
  std::optional<gs::estimation::IdentificationResult> result;
  for (int i = 0; i < 200 && !result; ++i) result = e.finish(t0_s + 2.0);
  return result;
}

double peak_excitation(MotorEqualiser& e, double t0_s) {
  double peak = 0.0;
  for (double t = t0_s; t < t0_s + 1.6; t += 0.001)
    peak = std::max(peak, e.flight().excitation(t).cwiseAbs().maxCoeff());
  return peak;
}

}  // namespace

TEST_CASE("A refused flight is flown again once, gently if it saturated; stopped when the pole comes") {
  MotorEqualiser e = equaliser();
  CHECK_FALSE(e.identifying());
  e.start_identification(10.0);
  CHECK(e.identifying());  // the pole waits
  const double designed = peak_excitation(e, 10.0);
  const auto saturated = fly(e, 10.0, true);
  REQUIRE(saturated);
  CHECK(saturated->refusal == IdentificationRefusal::saturated);
  REQUIRE(e.retry_due());
  CHECK(e.identifying());  // still: the retry is due
  e.start_retry(20.0);
  CHECK_FALSE(e.retry_due());
  CHECK(e.identifying());
  CHECK(peak_excitation(e, 20.0) == Approx(MotorEqualiser::kGentleAmplitude * designed));
  const auto again = fly(e, 20.0, true);
  REQUIRE(again);
  CHECK_FALSE(e.retry_due());  // once only
  CHECK_FALSE(e.identifying());

  SECTION("stopped when the vehicle takes the pole") {
    e.start_identification(30.0);
    fly(e, 30.0, true);
    e.start_retry(40.0);
    e.cancel_retry();
    CHECK_FALSE(e.flight().running());
    CHECK(e.flight().excitation(40.5).isZero());
  }
  SECTION("a flight refused for another reason is flown again as designed") {
    e.start_identification(30.0);
    std::optional<gs::estimation::IdentificationResult> silent;  // no telemetry came back
    for (double t = 30.0; t < 31.6; t += 0.005) e.flight().command_sent(t, e.flight().excitation(t));
    for (int i = 0; i < 10 && !silent; ++i) silent = e.finish(32.0);
    REQUIRE(silent);
    CHECK(silent->refusal == IdentificationRefusal::no_telemetry);
    REQUIRE(e.retry_due());
    e.start_retry(40.0);
    CHECK(peak_excitation(e, 40.0) == Approx(designed));
  }
  SECTION("a take-off's flight is not stopped by it") {
    e.start_identification(30.0);
    e.cancel_retry();
    CHECK(e.flight().running());
  }
}
