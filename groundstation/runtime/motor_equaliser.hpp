// One vehicle's rate response as the ground station manages it: each take-off's identification
// flight (identification_flight.hpp), its latest fit, and what the firmware is set to as far as
// the ground station knows: its equaliser's motor lag and its rate loop's inertia (over the
// airframe file's). A SET_MOTOR_TIME_CONSTANT or SET_INERTIA_SCALE counts only once acknowledged:
// a refused or lost one leaves what the vehicle had, which the next fit is flown and compared
// against.
// It sends nothing itself: the runtime sends the command and hands over its handle
// (motor_equaliser_test.cpp).
#pragma once

#include <cstdint>
#include <optional>

#include "groundstation/estimation/rate_response.hpp"
#include "groundstation/link/ground_link.hpp"
#include "groundstation/runtime/identification_flight.hpp"

namespace gs::runtime {

// SET_MOTOR_TIME_CONSTANT's argument for `lag_s`: microseconds, rounded.
std::int32_t motor_lag_argument_us(double lag_s);
// SET_INERTIA_SCALE's argument for `scale`: per mille, rounded.
std::int32_t inertia_scale_argument(double scale);

// A value set on board by a command: what the vehicle acknowledged, and the command in flight.
class OnBoardSetting {
 public:
  explicit OnBoardSetting(double value) : value_(value) {}
  // The command setting `value` was sent as `handle`.
  void sent(double value, const link::CommandHandle& handle) {
    sent_ = value;
    pending_ = handle;
  }
  const std::optional<link::CommandHandle>& pending() const { return pending_; }
  // The command in flight has come to `state` (as the link knows it): accepted, its value is set.
  void settle(link::CommandState state);
  double value() const { return value_; }

 private:
  double value_;                                // as acknowledged
  std::optional<link::CommandHandle> pending_;  // in flight
  double sent_ = 0.0;                           // its value
};

class MotorEqualiser {
 public:
  MotorEqualiser() : MotorEqualiser(IdentificationFlight{}, 0.0) {}
  // `design_lag_s`: what the firmware's equaliser starts from (its rate loop's design time constant).
  MotorEqualiser(const IdentificationFlight& flight, double design_lag_s)
      : flight_(flight), lag_(design_lag_s), inertia_(1.0) {}

  IdentificationFlight& flight() { return flight_; }
  const IdentificationFlight& flight() const { return flight_; }
  // Starts this take-off's identification flight against the lag set on board.
  void start_identification(double now_s);
  // A take-off's flight that was refused is flown once more, still, at the vehicle's target: one
  // the motors saturated with doublets kGentleAmplitude as large (a slow, heavy vehicle: 59 ms,
  // inertia 1.25, saturated at 1.5 rad/s, flew unequalised and crashed: hil campaign --plant
  // hil/config/envelope.yaml, attempts 92 and 107), any other as designed (a thrower with 67-72 ms
  // motors, its take-off's flight fitted while it climbed to the throw's origin, was refused at the
  // search's edge or not confident, balanced at 30 ms and dropped the pole onto itself: hil campaign
  // --plant hil/config/envelope/motors_60ms.yaml, 4 crashes in 49 attempts). The runtime starts it
  // when the vehicle holds its target without the pole.
  bool retry_due() const { return retry_due_; }
  void start_retry(double now_s);
  // The vehicle is no longer free to fly it (it holds the pole, lands): not started, or stopped.
  void cancel_retry();
  // An identification flight is flying, or its retry is due: a pole put on now would stop the one
  // and cancel the other.
  bool identifying() const { return retry_due_ || flight_.running(); }
  static constexpr double kGentleAmplitude = 0.5;
  // The take-off's flight and its retry are over (or the retry was cancelled), and the last fit
  // was refused: what the equaliser is set to was not measured on this take-off.
  bool refused() const { return identified_ && !identified_->identified && !identifying(); }

  // The equaliser's lag (SET_MOTOR_TIME_CONSTANT) and the rate loop's inertia scale
  // (SET_INERTIA_SCALE) on board.
  OnBoardSetting& lag() { return lag_; }
  OnBoardSetting& inertia() { return inertia_; }

  // The identification flight's fit once it is over (kept as identified()), else nothing.
  std::optional<estimation::IdentificationResult> finish(double now_s);

  const std::optional<estimation::IdentificationResult>& identified() const { return identified_; }
  double equalised_s() const { return lag_.value(); }
  double inertia_scale() const { return inertia_.value(); }

 private:
  IdentificationFlight flight_;
  std::optional<estimation::IdentificationResult> identified_;
  OnBoardSetting lag_;
  OnBoardSetting inertia_;
  bool retrying_ = false;  // the flight running is the retry
  bool retry_due_ = false;
  double retry_amplitude_ = 1.0;  // of the designed doublets
};

}  // namespace gs::runtime
