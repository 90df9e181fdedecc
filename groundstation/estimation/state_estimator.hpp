// The ground station's estimator (Section IV): both vehicles from their motion-capture poses and
// commands, and the pole by a hybrid estimator with one EKF per mode (free flight (20); on
// vehicle 1 or 2, (30)), the mode chosen from the innovations and from physical evidence, the
// chosen estimate fed back to the other modes. Time is always passed in.
//
// One update (a motion-capture frame at t):
//  1. Everything is propagated to t in steps of at most max_step_s, split at command changes:
//     the vehicles by their observers (commands drive them), the pole's active mode and its
//     candidates by their EKFs (the free-flight candidate, which no command or plate drives,
//     once over the whole interval). Dropped frames are coasted through the same way, the
//     covariances growing with the process noise.
//     Hard evidence is checked inside each step, and the switch is placed at the event:
//       - launch: in an on-vehicle mode, the plate's normal force F_N (pole_on_vehicle_ekf.hpp)
//         falling below -(launch_margin + launch_sigmas sigma): the contact is unilateral, so the
//         pole is free from the instant F_N crossed zero;
//       - impact: in free flight, the pole's lower end crossing a plate's plane inside its rim
//         while closing on it: the pole cannot pass through the plate; the impact map (35)-(40)
//         gives the on-vehicle state.
//  2. The vehicles are corrected with their poses.
//  3. The pole: each evaluated filter's innovation; an impact reported by a vehicle (IMPACT frame)
//     switches at once when the measured pole's lower end is at that plate, and otherwise
//     favours that mode in the CUSUM selection (mode_selector.hpp) for impact_report_window_s
//     (the CUSUM rests for switch_hold_off_s after any switch, and does not weigh the plate the
//     pole was launched from for launch_hold_off_s after the launch, nor free flight for a pole
//     pressed onto its plate or on a throwing vehicle); each filter is judged on the motion
//     capture's noise, whatever its gain trusts; a pose no filter explains is
//     rejected as a glitch (re-initialising after several in a row); then all evaluated filters
//     are corrected and the candidates not accumulating evidence are re-seeded from the chosen
//     estimate (pole_mode_conversion.hpp).
//
// Time: frames carry the capture time of their poses (the motion-capture system's clock);
// impact reports the impact's time on the same clock (the link converts the vehicle's clock with
// TIMESYNC). Commands are stamped with the time they act on the vehicle.
//
// Latency compensation: predicted() propagates a copy of the estimator (commands, mode switches
// and all) to the time a command will act, its states only: the covariances stay as they were
// at the last frame (propagation.hpp), which is most of the saving.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "groundstation/estimation/estimator_health.hpp"
#include "groundstation/estimation/mocap_pose.hpp"
#include "groundstation/estimation/mode_selector.hpp"
#include "groundstation/estimation/pole_free_flight_ekf.hpp"
#include "groundstation/estimation/pole_length.hpp"
#include "groundstation/estimation/pole_mode.hpp"
#include "groundstation/estimation/pole_mode_conversion.hpp"
#include "groundstation/estimation/pole_on_vehicle_ekf.hpp"
#include "groundstation/estimation/vehicle_observer.hpp"

namespace gs::estimation {

struct StateEstimatorConfig {
  VehicleObserverParams vehicle;
  PoleFreeFlightEkfParams free_flight;
  PoleOnVehicleEkfParams on_vehicle;
  ModeSelectorParams selector;
  PlateContactGate candidate_gate;  // where an on-vehicle candidate is seeded at all
  // The pole's half length learnt while it rests on a plate (pole_length.hpp), in force in the
  // filters from its first sample on (the mean so far until it is learnt); false: the configured
  // L throughout. The learner's nominal is the configured L.
  bool learn_pole_length = true;
  PoleLengthParams pole_length;
  // After a switch the innovations do not switch again for this long: a freshly seeded filter's
  // innovations are unreliable while it converges (e.g. through a compliant plate's first
  // tens of milliseconds after an impact). Physical evidence still switches at once.
  double switch_hold_off_s = 0.05;
  // After a launch the innovations do not return the pole to the plate it left for this long.
  // A pole leaving a tilted plate turning slides its end along the plate's plane for tens of
  // milliseconds (on the arena envelope: 5 mm above it 46 mm from where it left, 0.14 s after
  // the contact force vanished), which the on-vehicle filter explains as well as the free flight;
  // the switch back, and the launch detected again from the on-vehicle estimate, seeded the free
  // flight with a velocity 0.8 m/s off (tests/hil/pole_launch_test.cpp). A pole that did not
  // leave comes back once this has passed.
  double launch_hold_off_s = 0.25;
  // Added to the free flight's rate uncertainty at a launch: the on-vehicle filter's is tight,
  // and the plate's push may go on after the launch is detected. With the hold-off, a launch
  // detected 70 ms before the push ended put the catch point 0.18 m off 0.1 s after the release,
  // with this 0.09 m (throw_through_firmware_test; 1 rad/s: 0.08 m, but on the arena envelope 7
  // catches judged out of reach at 0.1 s after the launch against 1). A launch found because the
  // on-vehicle filter lost its geometry gets the same: that filter's rate is no better then.
  double launch_rate_sigma_radps = 0.1;
  double max_step_s = 0.005;
  double command_timeout_s = 0.2;  // an older command no longer drives a vehicle's model
  // A gap in the frames longer than this is not coasted through (it would cost a step per
  // max_step_s and the estimate means nothing after it): the estimator starts over from the
  // next poses, as after its first frame.
  double max_coast_s = 1.0;
  // Launch (see the header comment). With the commands driving the vehicle model the estimated
  // F_N is good to about 0.5 m/s^2 (sigma ~0.6); without them the vehicle's acceleration, and
  // so F_N, is known only to several m/s^2 and the sigma term keeps noise from launching.
  double launch_margin_mps2 = 0.2;
  double launch_sigmas = 1.0;
  // The innovations do not take the pole off a plate that presses it on harder than this (the
  // on-vehicle filter's F_N per unit pole mass above pressed_min_mps2 and pressed_sigmas of its
  // sigma): pressed on, it is not in free flight, and its launch is the normal force's to find.
  // Noisy poses (3 mm / 3 mrad) on a slow-motored thrower made the selector call the pole free and
  // back 8-38 times a pass on the arena envelope, each time taking the throw's feedback off the
  // plate's pole for tens of milliseconds (state_estimator_test counts them). Above g and the
  // balancing's own accelerations, so that a balanced pole knocked off is still found by the
  // innovations: only the throw's pressing part is guarded.
  double pressed_sigmas = 3.0;
  double pressed_min_mps2 = 11.5;
  // Impact on a plate (see the header comment).
  double impact_radial_margin_m = 0.02;
  double impact_min_approach_speed_mps = 0.3;
  double impact_rate_sigma_mps = 0.2;  // post-impact rate uncertainty (impact model)
  // IMPACT frames from the vehicles.
  double impact_report_window_s = 0.15;
  PlateContactGate impact_report_gate{0.5 * pa::kPlateDiameter_m, 0.04, 0.05, 1.3};
  // A pole pose that no mode's filter explains (NIS above this in every evaluated filter) is a
  // glitch and is ignored; after pole_max_rejections such poses in a row the pole estimate
  // starts over from the pose (the pole really is elsewhere, e.g. moved by hand).
  double pole_outlier_nis = 1e4;
  int pole_max_rejections = 5;
  // The pole first seen in the air.
  double initial_velocity_sigma_mps = 3.0;
  double initial_rate_sigma_radps = 10.0;
  // The drag scale k at each launch: the value learnt in the last caught flight (or 1) and this
  // sigma. 0.1 trades the early prediction when the coefficients are right (a wide prior lets
  // k wander while the flight has told little) against the speed of learning a wrong one.
  double drag_scale_sigma = 0.1;
  bool carry_drag_scale = true;
};

struct MocapFrame {
  double t_s = 0.0;
  std::array<std::optional<MocapPose>, 2> vehicle;  // vehicle 1, vehicle 2
  std::optional<MocapPose> pole;
};

struct PoleEstimate {
  bool valid = false;  // false until the pole has been seen
  double t_s = 0.0;
  PoleMode mode = PoleMode::free;
  model::PoleState state;  // n in the motion capture's convention (the pole's body z-axis)
  PoleCovariance covariance = PoleCovariance::Identity();  // of (p, v, n, Omega)
  double drag_scale = 1.0;
};

enum class SwitchReason : std::uint8_t {
  initial,         // the pole's first sighting
  contact_force,   // launch: the plate's normal force turned negative
  plate_contact,   // impact: the lower end reached a plate
  impact_report,   // impact: an IMPACT frame with the end at the plate
  innovation,      // the CUSUM of the innovations
  filter_invalid,  // the active on-vehicle filter lost its geometry (pole fell over)
  reinitialised,   // no mode explained the pole's poses: started over from them
};
inline constexpr int kSwitchReasonCount = static_cast<int>(SwitchReason::reinitialised) + 1;
std::string_view switch_reason_name(SwitchReason reason);

struct ModeSwitch {
  double event_t_s = 0.0;     // when the event happened (estimated)
  double detected_t_s = 0.0;  // the estimator time at which it was decided
  PoleMode from = PoleMode::free;
  PoleMode to = PoleMode::free;
  SwitchReason reason = SwitchReason::initial;
};

class StateEstimator {
 public:
  static constexpr int kSwitchLogCapacity = 64;
  static constexpr int kCommandQueueCapacity = 32;

  explicit StateEstimator(const StateEstimatorConfig& config = {});

  // The input that vehicle (1 or 2) applies from t_s on (commands arrive in time order; a
  // command for the future, e.g. sent now to act after the link latency, is queued).
  void set_command(pa::VehicleId vehicle, double t_s, const model::VehicleInput& input);
  // An impact the vehicle's firmware reported, at t_s on the estimator's clock.
  void report_impact(pa::VehicleId vehicle, double t_s);
  // Whether `vehicle` is throwing (the runtime's task `throwing`): the pole it holds is pushed
  // on and leaves by its normal force (the launch), not by the innovations. The pressed guard
  // (pressed_min_mps2) let a switch through where a slow thrower's last 50 ms pressed less, and
  // the free filter then ran on a pole still pushed: the catch was missed (docs/architecture.md).
  void set_throwing(pa::VehicleId vehicle, bool throwing) {
    if (pa::is_act_vehicle(vehicle)) throwing_[pa::act_slot(vehicle)] = throwing;
  }
  // How far the pole filter on `vehicle` trusts the motion capture (PoleTrust).
  void set_pole_measurement_sigma(pa::VehicleId vehicle, double position_m, double direction_rad);
  // Processes a frame; frames older than the estimator's time are counted and ignored.
  void update(const MocapFrame& frame);
  // Propagates to t_s without measurements (the frame did not come); a gap longer than
  // config().max_coast_s starts over instead.
  void advance_to(double t_s);

  double time() const { return t_s_; }
  PoleMode mode() const { return selector_.active(); }
  PoleEstimate pole() const;
  bool vehicle_initialised(pa::VehicleId vehicle) const;
  VehicleEstimate vehicle(pa::VehicleId vehicle) const;
  PlateKinematics plate(pa::VehicleId vehicle) const;
  // The plate's normal force under the pole (on-vehicle modes; nullopt in free flight).
  std::optional<NormalForceEstimate> normal_force() const;
  // The pole model with the estimated drag scale (for catch-point prediction).
  model::PoleParams pole_model() const { return free_.scaled_model(); }

  // Latency compensation: the estimator propagated to t_s >= time() without covariances (see the
  // header); a copy to read pole(), vehicle(), plate() from.
  StateEstimator predicted(double t_s) const;
  PoleEstimate predict_pole(double t_s) const;
  VehicleEstimate predict_vehicle(pa::VehicleId vehicle, double t_s) const;

  EstimatorHealth health(double t_now_s) const;
  std::uint64_t switch_count() const { return switch_count_; }
  // Those for one reason: a campaign counts the switches on the innovations, the selector's
  // health (a balanced pole called free and back is a filter that explains its poses badly).
  std::uint64_t switch_count(SwitchReason reason) const {
    return switch_count_by_reason_[static_cast<int>(reason)];
  }
  std::uint64_t start_over_count() const { return start_overs_; }
  std::optional<ModeSwitch> last_switch() const;
  // Up to kSwitchLogCapacity most recent switches, oldest first.
  std::vector<ModeSwitch> recent_switches() const;

  // The filters, for tests and diagnostics.
  const PoleFreeFlightEkf& free_flight_filter() const { return free_; }
  const PoleOnVehicleEkf& on_vehicle_filter(pa::VehicleId vehicle) const {
    return on_[pa::act_slot(vehicle)];
  }
  const ModeSelector& selector() const { return selector_; }
  const PoleLengthLearner& pole_length() const { return pole_length_; }
  const StateEstimatorConfig& config() const { return config_; }

 private:
  struct TimedCommand {
    double t_s = 0.0;
    model::VehicleInput input;
  };
  struct CommandQueue {
    std::array<TimedCommand, kCommandQueueCapacity> items;
    int head = 0;
    int count = 0;
    const TimedCommand& at(int i) const { return items[(head + i) % kCommandQueueCapacity]; }
  };

  const model::VehicleInput* command_at(int index, double t_s) const;
  double next_command_change(double after_t_s, double until_t_s) const;
  void drop_old_commands(double t_s);
  // One step; `normal_force` holds the plate's normal force under the pole at its start in an
  // on-vehicle mode (none: computed there), and then at its end (the next step's start: computed
  // once for both).
  void step(double h, std::optional<NormalForceEstimate>& normal_force);
  void step_pole(double h, const std::array<PlateKinematics, 2>& before,
                 const std::array<PlateKinematics, 2>& after,
                 std::optional<NormalForceEstimate>& normal_force);
  void switch_to(PoleMode mode, SwitchReason reason, double event_t_s, double detected_t_s);
  void start_over(double t_s);
  void reseed_candidates();
  // Whether reseed_candidates() re-seeds the free-flight candidate from the active plate's filter
  // (an on-vehicle mode whose vehicle is known, the candidate gathering no evidence).
  bool free_candidate_reseeded() const;
  void initialise_pole(const PoleMeasurement& m, SwitchReason reason);
  void update_pole(const PoleMeasurement& m);
  void learn_pole_length(const MocapFrame& frame);
  PoleEstimate pole_now() const;
  bool impact_report_pending(int index) const;

  StateEstimatorConfig config_;
  Propagation propagation_ = Propagation::mean_and_covariance;
  double t_s_ = 0.0;
  bool started_ = false;
  std::array<VehicleObserver, 2> vehicles_;
  std::array<CommandQueue, 2> commands_;
  std::array<double, 2> impact_report_t_s_;
  std::array<bool, 2> throwing_{};
  bool pole_seen_ = false;
  PoleFreeFlightEkf free_;
  double free_behind_s_ = 0.0;  // the free-flight candidate's propagation owed (step_pole)
  std::array<PoleOnVehicleEkf, 2> on_;
  std::array<bool, 2> on_candidate_valid_{};
  ModeSelector selector_;
  PoleLengthLearner pole_length_;
  double drag_scale_ = 1.0;  // seed of k at the next launch
  double mode_since_s_ = 0.0;
  double last_switch_detected_s_ = -1e300;
  int launched_from_ = -1;  // the slot whose plate the pole last left (by force or lost geometry), or -1
  double launch_t_s_ = -1e300;
  // Health and the switch log (fixed size, so that a copy for prediction is cheap).
  std::array<BodyHealthTracker, 2> vehicle_health_;
  BodyHealthTracker pole_health_;
  std::uint64_t frames_ = 0;
  std::uint64_t frames_out_of_order_ = 0;
  std::uint64_t start_overs_ = 0;
  int pole_rejections_ = 0;
  std::array<ModeSwitch, kSwitchLogCapacity> switch_log_{};
  std::uint64_t switch_count_ = 0;
  std::array<std::uint64_t, kSwitchReasonCount> switch_count_by_reason_{};
  // pole() since the state last changed (update and advance_to reset it; a command, an impact
  // report or a filter's measurement sigma changes nothing it reads until then): the runtime reads
  // it several times a frame, between the commands it sends, each an on-vehicle filter's
  // conversion to free flight.
  mutable std::optional<PoleEstimate> pole_estimate_;
};

}  // namespace gs::estimation
