// The scripted self-test flight: the firmware core flown on board against a small synthetic
// rigid-body vehicle (gyro and accelerometer from its motion), through a setpoint stream of
// hover, a rate manoeuvre, a caught pole's impact, and a link loss. The same scenario runs on
// the Cortex-M4 image in QEMU, in the host demo and in the Catch2 tests. No heap.
#pragma once

#include <cstdint>

namespace fw::selftest {

// Measures each 1 kHz tick of the firmware core (the port brackets Vehicle::tick with it).
class TickProbe {
 public:
  virtual void before_tick() = 0;
  virtual void after_tick() = 0;

 protected:
  ~TickProbe() = default;
};

// What the scenario observed, for a person to read and for tests to assert.
struct Result {
  bool pass = false;
  const char* failure = nullptr;             // the first failed check; nullptr when passed
  std::uint32_t ticks = 0;                   // 1 kHz ticks flown
  float hover_rate_error_max_radps = 0;      // steady hover, worst body-rate error
  float manoeuvre_rate_error_rms_radps = 0;  // tracking during the rate manoeuvre
  float impact_detection_latency_ms = -1;    // IMPACT confirmed after the true onset
  float impact_timestamp_error_ms = -1;      // reported onset minus the true onset
  float failsafe_hover_after_ms = -1;        // levelled hover (a hold) after the last fresh setpoint
  float descent_after_ms = -1;               // descent after the levelled hover began (hold + failsafe hover)
  float motors_off_after_landing_ms = -1;    // motors off after ground contact
};

// Run the whole scenario. `probe` may be nullptr.
Result run(TickProbe* probe);

}  // namespace fw::selftest
