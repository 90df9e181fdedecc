// Impact detector: recognises the pole landing on the catching plate from the IMU within a
// few milliseconds, timestamps its onset, tells it apart from a crash and from the
// accelerations of a throw, and reports it (the caller turns a report into an IMPACT frame).
//
// Physics. The accelerometer measures the specific force f = (thrust + contact forces) / m_v.
// In free flight its body-z component follows the commanded collective a_q through the motor
// lag. The pole (m_p = 0.03 kg, paper Section VII) hitting the plate pushes the vehicle down:
// f_z drops by about m_p dv / (m_v t_contact) - some 15-50 m/s^2 for 2-6 m/s on the shock
// absorber (a few ms of contact) - with a small rate kick from the off-centre contact. A throw
// moves a_q between about 2 and 20 m/s^2 and the rates up to 10 rad/s, but f follows a_q
// through the lag, so it leaves no residual. A crash pushes up or sideways, peaks at tens to
// hundreds of m/s^2 and spins the vehicle by tens of rad/s.
//
// Method, per sample:
//  1. expected f_z = commanded collective through a first-order lag (motor_time_constant_s);
//     residual q = f - (0, 0, expected f_z).
//  2. An event starts when q has changed by more than trigger_mps2 from its value
//     reference_delay_samples ago (the reference, frozen from then on); slow changes of q never
//     start one. It is confirmed after confirm_samples consecutive samples above the trigger.
//  3. The onset time is interpolated on the rising edge (the line through its first two samples,
//     extended back to zero), not the confirmation time.
//  4. The peak of |q - reference| is tracked and refined by a parabola through the largest
//     sample and its neighbours (a 3 ms half-sine is only three samples wide at 1 kHz).
//  5. Classification: crash when the peak, the lateral part or the rate change exceeds its
//     threshold (any direction; while a landing is expected, a push up the body z-axis - the
//     floor - is a crash only above the higher touchdown peak or by the rate change, since the
//     floor's friction may push sideways as hard as it pushes up); otherwise a push along -z is a
//     catch_impact when a catch is expected and an unexpected_impact when not; any other push
//     is an unexpected_impact.
//
// Every event is reported exactly twice, on different ticks:
//  - stage `detected` on the sample that confirms it (at most a few ms after the onset), with
//    the peak so far and a provisional classification (already `crash` when a threshold has
//    been crossed) - the moment to start the on-board catch reaction;
//  - stage `classified` when the residual returns below release_mps2, a crash threshold is
//    crossed, or event_window_us has passed since the onset, with the final peak and class -
//    the moment to send the IMPACT frame. Both carry the same onset time and count.
// A crash classified before its contact ends keeps the detector busy until the contact ends (it
// is one event). After an event's contact ends, only crash-level changes start a new one for
// refractory_us (the absorber's ringing is not a second impact, a crash just after a catch is).
//
// Non-finite input is ignored: no report, state untouched. Clocks are free-running uint32
// microseconds and may wrap. Float, no heap, bounded time: the samples of an event are measured
// against its reference as they arrive, so the longest path (the sample that starts an event)
// measures the reference_delay_samples samples since the reference once, and no sample replays
// the whole rise.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "fw/config.hpp"
#include "fw/types.hpp"
#include "pa/protocol.hpp"

namespace fw {

struct ImpactInput {
  std::uint32_t t_us = 0;              // vehicle clock of the IMU sample
  Vec3f accel_mps2{};                  // specific force, body frame (+g on z when level at rest)
  Vec3f gyro_radps{};                  // body rates
  float commanded_thrust_mps2 = 0.0f;  // collective applied to the motors over the interval ending here
  bool catch_expected = false;         // inside a catch window (EXPECT_CATCH)
  bool landing_expected = false;       // descending to land: the floor may push up
};

enum class ImpactStage : std::uint8_t {
  detected = 1,    // confirmed; peak so far, provisional class
  classified = 2,  // finished; final peak and class
};

struct ImpactEvent {
  std::uint32_t t_us = 0;  // estimated onset on the vehicle clock (not the detection time)
  float peak_mps2 = 0.0f;  // largest change of the specific-force residual, m/s^2
  pa::proto::ImpactClass classification = pa::proto::ImpactClass::unexpected_impact;
  ImpactStage stage = ImpactStage::detected;
  std::uint8_t count = 0;         // this event's number since boot, wrapping (IMPACT count)
  std::uint32_t detected_us = 0;  // the sample that confirmed the event
  bool touchdown = false;  // the floor's push up the body z-axis while a landing was expected, not a crash
};

class ImpactDetector {
 public:
  static constexpr std::size_t kHistory = 16;  // samples kept for the reference and the onset
  static constexpr std::uint8_t kMaxReferenceDelay = 8;
  static constexpr std::uint8_t kMaxConfirmSamples = 7;

  ImpactDetector(const ImpactDetectorConfig& config, const AirframeConfig& airframe);

  // One IMU sample. Returns true when `out` holds a report (see the stages above); at most one
  // report per sample, exactly one `detected` and one later `classified` per event.
  bool update(const ImpactInput& in, ImpactEvent& out);

  // Forget the signal history and any event in progress; the count since boot is kept.
  void reset();

  std::uint8_t count() const { return count_; }  // events detected since boot, wrapping
  bool in_event() const { return phase_ != Phase::idle; }
  float expected_thrust_mps2() const { return expected_mps2_; }  // the motor-lag model's output
  Vec3f residual_mps2() const;  // latest specific force minus the expected thrust (zero before any sample)

 private:
  // idle: watching; pending: above the trigger, not yet confirmed; active: confirmed, not yet
  // classified; tail: classified early (a crash), waiting for the contact to end.
  enum class Phase : std::uint8_t { idle, pending, active, tail };
  struct Sample {
    std::uint32_t t_us = 0;
    Vec3f residual_mps2{};
    Vec3f gyro_radps{};
  };
  // What an event has shown so far, against the frozen reference.
  struct Accumulator {
    float peak_mps2 = 0.0f;         // largest sampled |q - reference|
    float before_peak_mps2 = 0.0f;  // the sample before the largest
    float after_peak_mps2 = 0.0f;   // the sample after it, once seen
    bool has_after = false;
    float peak_z_mps2 = 0.0f;  // signed z change at the largest sample
    float lateral_max_mps2 = 0.0f;
    float rate_change_max_radps = 0.0f;
    float last_mps2 = 0.0f;  // |q - reference| of the latest sample
  };
  // The rising edge so far: the latest sample inside the onset band and the first two after it.
  struct RisingEdge {
    std::uint32_t quiet_us = 0;  // the latest sample with |q - reference| < onset_mps2
    std::uint8_t count = 0;      // samples after it (counted up to 2), the first two kept:
    std::uint32_t first_us = 0;
    float first_mps2 = 0.0f;  // |q - reference|
    std::uint32_t second_us = 0;
    float second_mps2 = 0.0f;
  };

  const Sample& history(std::size_t samples_ago) const;
  // returns |q - reference| of s
  static float add(Accumulator& acc, const Sample& s, const Sample& reference);
  void begin_event(std::size_t delay);  // the reference delay samples ago and the samples since
  // add() the samples from oldest_age to the latest, following the rising edge.
  void accumulate(std::size_t oldest_age, const Sample& reference, Accumulator& acc, RisingEdge& edge) const;
  bool triggered(const Vec3f& change_mps2, bool crash_level_only) const;
  bool touchdown(const Accumulator& acc) const;  // a landing expected and the push up the body z-axis
  bool downward(const Accumulator& acc) const;   // the push down the body z-axis, as a pole's
  bool crash_seen(const Accumulator& acc, float peak_mps2) const;
  pa::proto::ImpactClass classify(const Accumulator& acc, float peak_mps2) const;
  float refined_peak() const;
  void confirm(std::uint32_t now_us, ImpactEvent& out);
  void finish(bool contact_over, ImpactEvent& out);

  ImpactDetectorConfig config_;
  float motor_time_constant_s_;
  float trigger2_;  // the squared levels triggered() compares with
  float crash_peak2_;
  float crash_lateral2_;

  bool started_ = false;
  std::uint32_t last_t_us_ = 0;
  float expected_mps2_ = 0.0f;
  bool has_lag_gain_ = false;  // the motor-lag step's gain for a step of lag_gain_step_us_
  std::int32_t lag_gain_step_us_ = 0;
  float lag_gain_ = 0.0f;
  std::array<Sample, kHistory> history_{};
  std::size_t newest_ = 0;  // index of the latest sample
  std::size_t filled_ = 0;  // samples held, up to kHistory

  Phase phase_ = Phase::idle;
  Sample reference_{};
  RisingEdge edge_{};              // pending only
  std::uint8_t above_ = 0;         // consecutive samples above the trigger (pending only)
  bool crash_level_only_ = false;  // the event began inside the refractory period
  bool catch_expected_ = false;    // a catch was expected at some sample of the event
  bool landing_expected_ = false;  // a landing was expected at some sample of the event
  Accumulator acc_{};
  std::uint32_t onset_us_ = 0;
  std::uint32_t detected_us_ = 0;

  bool has_settled_ = false;  // references must be no older than settled_us_ (the end of the last excursion)
  std::uint32_t settled_us_ = 0;
  bool has_last_event_ = false;
  std::uint32_t last_event_end_us_ = 0;
  std::uint8_t count_ = 0;
};

}  // namespace fw
