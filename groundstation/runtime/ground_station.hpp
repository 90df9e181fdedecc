// The ground-station runtime: the one object that flies the mission, as a loop over named
// pieces. It owns the estimator, the link, both vehicles' sequencers, the task controllers, the
// throw book, the catch coordinator and the learner, and is driven from outside by three calls
// and nothing else:
//   on_mocap(frame, now)  a motion-capture frame arrived: the laws' time step
//                        (frame_interval.hpp), estimator update, each vehicle's thrust-gain
//                        sample (thrust_compensation.hpp), the attempt's phases
//                        (attempt_phases.hpp), then for each vehicle its condition facts and word
//                        (condition_facts.hpp), its sequencer step, the new task's entry actions
//                        (task_entry.hpp) and its task's law (task_control.hpp) to a setpoint,
//                        its thrust over the gain;
//   on_frame(frame, now)  a frame from the ground CAN bus (heartbeats, acks, IMPACT, TIMESYNC),
//                        decoded once by the link, the rates routed to the identification;
//   tick(now)            link housekeeping (heartbeats, retries, TIMESYNC, lost vehicles), the
//                        mission commands (link/mission_commands.hpp), the motors' identification
//                        and the lag set on board (motor_equaliser.hpp).
// No clock, no thread: `now` is the ground clock, which is also the clock the motion capture
// stamps its frames with (in simulation both are the plant's time). The same object runs in the
// lockstep arena (hil/sil), in `hil run`'s plant exchange and in `groundstation run`
// (service/process.hpp), the real-time process.
//
// What it sees is only what an arena gives a ground station: motion-capture poses and vehicle
// frames. Every controller runs on the estimator's state predicted forward to the time its
// command acts on the vehicle (command_lead_s: the radio's latency plus the firmware's tick),
// never on plant truth; the build enforces it (groundstation never links hil).
//
// Frames: one RATE_THRUST per vehicle per motion-capture frame (200 Hz) in every task that flies
// setpoints; none in `landing` (LAND flies on board) and `failsafe` (the firmware levels and
// descends when the stream stops).
//
// An attempt (Section VII-B, attempt.hpp): the thrower balances the pole at the throw's origin,
// the catcher waits at its waiting point; the thrower flies the optimal throw (34) with the
// TV-LQR (planning/throw_book.hpp), releases and retreats; the catcher starts its z manoeuvre so
// that it comes to rest at the catching height at the expected catching instant, re-plans its
// xy correction to the latest catch-point prediction at every frame and tracks it in closed loop
// (catch_coordinator.hpp); after the impact it holds still while the pole swings up, then
// balances it. Attempts are admitted by attempt_admission.hpp and closed by attempt_close.hpp:
// throw by throw the learner (adaptation/learner.hpp, Section VI) moves the catching height, the
// waiting point and the offset bias.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "groundstation/adaptation/catch_energy.hpp"
#include "groundstation/adaptation/identification_memory.hpp"
#include "groundstation/adaptation/learner.hpp"
#include "groundstation/control/task_laws.hpp"
#include "groundstation/control/throw_frame.hpp"
#include "groundstation/estimation/mocap_noise.hpp"
#include "groundstation/estimation/rate_response.hpp"
#include "groundstation/estimation/state_estimator.hpp"
#include "groundstation/estimation/thrust_gain.hpp"
#include "groundstation/link/ground_link.hpp"
#include "groundstation/link/mission_commands.hpp"
#include "groundstation/mission/condition_word.hpp"
#include "groundstation/mission/vehicle_sequencer.hpp"
#include "groundstation/model/vehicle_limits.hpp"
#include "groundstation/planning/throw_book.hpp"
#include "groundstation/runtime/attempt.hpp"
#include "groundstation/runtime/attempt_admission.hpp"
#include "groundstation/runtime/attempt_close.hpp"
#include "groundstation/runtime/attempt_phases.hpp"
#include "groundstation/runtime/catch_coordinator.hpp"
#include "groundstation/runtime/condition_facts.hpp"
#include "groundstation/runtime/frame_interval.hpp"
#include "groundstation/runtime/motor_equaliser.hpp"
#include "groundstation/runtime/task_control.hpp"
#include "groundstation/runtime/task_entry.hpp"
#include "groundstation/runtime/throw_geometry.hpp"
#include "groundstation/runtime/thrust_compensation.hpp"

namespace gs::runtime {

struct GroundStationConfig {
  link::GroundLinkConfig link;
  // The vehicle observers' pose gate opened to NIS 1000 (from 60): through the throw's fastest
  // phase their model misses by enough (it did with the first-order rate model it had then) that
  // five poses in a row failed the gate and the observer re-initialised with zero velocity
  // (measured: vz 0 against -0.6 m/s true), which threw the TV-LQR off the plan.
  //
  // The vehicles' poses trusted as 5 mm / 5 mrad, 5 times an arena's typical noise. Measured on
  // the arena envelope (0.5-3 mm of noise, motors 20-60 ms; `hil campaign --attempts 300 --plant
  // hil/config/envelope.yaml`), the pole filters at 3 mm: the vehicles at 1 mm caught 185, at
  // 3 mm 211, 5 mm 212, 8 mm 210; told each plant's own noise, 190. The built-in plant catches
  // 400 of 400 at 5 mm as at 1 mm. The model leaves out what a vehicle off its airframe file
  // does (lag, thrust): trusting it more smooths the noise the controllers act on more than it
  // costs in lag.
  estimation::StateEstimatorConfig estimator = [] {
    estimation::StateEstimatorConfig c;
    c.vehicle.outlier_nis = 1000.0;
    c.vehicle.mocap_position_sigma_m = 5e-3;
    c.vehicle.mocap_attitude_sigma_rad = 5e-3;
    return c;
  }();
  model::VehicleLimits limits{1.0, 20.0, 10.0};
  // The time from a setpoint's computation to its use on board: the radio's latency and jitter
  // (8 + 1 ms on average in the default arena), up to one firmware tick until the vehicle's link
  // guard starts checking it, and the two more ticks its check takes (docs/security.md).
  double command_lead_s = 0.012;
  // The task laws' time step from the frames' arrivals: at most 0.05 s after a gap, 0.005 s (one
  // 200 Hz frame) for the first (runtime/frame_interval.hpp).
  FrameIntervalSettings frame_interval;
  // The throw's origin: where the thrower's plate centre hovers before the throw. The plan dips
  // 1.1 m below it, and the vehicle's feet hang 0.2 m below its centre; from 1.5 m the feet
  // touched the floor at the bottom of the dip (measured), so 2 m.
  Eigen::Vector3d throw_origin_m{0.0, 0.0, 2.0};
  // The direction vehicle 1 throws in, from +x towards +y (control/throw_frame.hpp). Vehicle 2
  // throws back: from where vehicle 1's throws come down (the adapted catch point, at the
  // origin's height), in the opposite direction, so that its throws come down where vehicle 1
  // throws from and passes go back and forth between two points.
  double throw_yaw_rad = 0.0;
  // Where each vehicle stands on the floor before take-off (x, y), and the take-off height.
  std::array<Eigen::Vector2d, 2> home_xy_m{Eigen::Vector2d(-1.0, 0.0), Eigen::Vector2d(1.0, 0.0)};
  double take_off_height_m = 1.0;
  // The task controllers' carrot, integral, take-off ramp, pole weight, release and throw
  // window (runtime/task_control.hpp).
  TaskControlSettings tasks;
  // When each condition bit holds (mission/condition_word.hpp). at_target: 5 cm and 0.1 m/s;
  // at_height 0.1 m below the target; a pole end within 8 cm of the plate (the plate's radius
  // 6 cm plus the pose noise) keeps the pole on it; upright below 0.5 rad (29 degrees); the
  // release's minimum thrust 0.3 s; balancing 2 s with the tilt below tasks.balance_settled_rad for
  // 1 s before a throw; a catcher clear of an aborted catch for 1 s. No pose of a vehicle for
  // 0.3 s: its estimate is lost (the link's rule, GroundLinkConfig::vehicle_timeout_s; motion
  // capture that hides a body for 100 ms, two or three times back to back, is predicted through
  // on the commanded inputs).
  mission::ConditionThresholds conditions;
  // Each vehicle's thrust gain, measured in flight (estimation/thrust_gain.hpp) while it hovers,
  // waits, balances or flies clear, above this height (clear of the legs' ground contact); the
  // setpoints carry a_q / k, so that every law flies the vehicle it was designed for.
  estimation::ThrustGainConfig thrust_gain;
  bool compensate_thrust_gain = true;
  double thrust_gain_min_height_m = 0.3;
  // Each take-off identifies the vehicle's motor lag from rate doublets once it is airborne
  // (runtime/identification_flight.hpp, from the firmware's rate loop as configured on board) and
  // sets it on board for the firmware's equaliser when it differs from what is set there by more
  // than motor_lag_tolerance_fraction: the fit's own accuracy (rate_response_test), so a vehicle
  // with the airframe's motors is left as it is. A refused fit keeps the last accepted one, which
  // with a store (adaptation_store_path) may be an earlier run's: it is set on board at every
  // arming, before the take-off's own fit (adaptation/identification_memory.hpp).
  bool identify_motors = true;
  estimation::RateLoopConfig rate_loop;
  estimation::RateResponseSettings rate_response;
  double motor_lag_tolerance_fraction = 0.1;
  // Each vehicle's pole filter trusts the poses by its motor lag as set on board and by the
  // noise measured on its own poses while it holds still or hovers (estimation::PoleTrust),
  // re-judged once a second.
  estimation::PoleTrust pole_trust;
  // A vehicle flies its part of an attempt only if its thrust at full command, k a_full (V/V_ref)^2
  // (below), is at least this fraction of what the part needs at its peak: the throw's planned peak thrust
  // (17.1 m/s^2) for the thrower, g plus the catch's a_max for the catcher; the throw saturates
  // for a moment and is caught all the same. Measured (hil fly --throws 20): both vehicles' thrust
  // at 0.8 (k a_q,max = 16.0 m/s^2) 19 of 19 caught; at 0.77 the take-off fails. At 0.95 the
  // corner 10 % heavier at thrust 0.9 (k 0.818) was refused from throw 10 of 50 on (its k read
  // 1 % low), every throw before it caught (both with a_q,max as the ceiling). With a_full: thrower
  // k >= 0.62 and catcher k >= 0.51 at full charge.
  double min_thrust_fraction = 0.9;
  // The firmware's battery reference (fw::BatteryConfig, the arena's configuration): it scales its
  // commands by (V_ref / V)^2 as the pack sags (docs/plant.md), so k no longer shows the sag but
  // the motors' ceiling does: a vehicle reporting V in TELEMETRY_STATUS delivers at most
  // k a_full (V / V_ref)^2. Measured: the corner with every range half way (85 % charge, thrust
  // 0.925) was refused with k from the sag alone; compensated, its k read 0.88, the throws were
  // flown and the thrower crashed against its ceiling (hil fly --series paper --seed 1).
  double battery_reference_voltage_V = 12.6;
  // The airframe's collective thrust at full command and the reference voltage, mass-normalised
  // (the airframe file, fw::AirframeConfig: 4 motor_thrust_max_N / mass_kg = 24.6 m/s^2). a_q,max
  // above is what the plans may ask of a vehicle; this is what its motors give at full command, so
  // a vehicle of gain k delivers at most k a_full (V / V_ref)^2, and its setpoints a_q / k may go
  // up to a_full. Measured: with a_q,max as the ceiling, 55 of 300 attempts on the arena envelope
  // were refused as too weak, vehicles that reach the throw's peak (hil campaign --attempts 300
  // --plant hil/config/envelope.yaml).
  double airframe_thrust_max_mps2 = 4.0 * 3.2 / 0.52;
  // Each catcher's catching height corrected from the pole's energy after its impacts.
  adaptation::CatchEnergySettings catch_energy;
  double launch_delay_s = 0.01;  // measured: the estimator calls the launch 10 ms after T
  // The throw's TV-LQR weights: the planner's defaults but a pitch-rate input tolerance of
  // 0.25 rad/s (R 16 times heavier). With the defaults (2 rad/s) the gains are 240 rad/s per
  // rad of pole tilt and 70 per rad/s of its rate: right on the plant's truth, but flown on the
  // estimate, the on-vehicle filter's few centiradians per second of rate error became rad/s of
  // command, the loop oscillated at ~3 Hz with the pitch rate saturating at 10 rad/s and the
  // vehicle ended the throw 1.4 m low (measured, seed 1). With 0.25 rad/s it ends 3 cm low and
  // within 0.01 m/s of the launch speed.
  planning::ThrowTrackingWeights throw_tracking = [] {
    planning::ThrowTrackingWeights w;
    w.input_tolerance(model::planar::kPitchRate) = 0.25;
    return w;
  }();
  // The catch manoeuvre (Section V, Fig. 7; catch_coordinator.hpp). Beyond the paper:
  // - xy_lead_s: the xy correction starts 0.5 s before t3 (catch_trajectory.hpp), 1.15 s instead
  //   of 0.65 s for the same travel. Measured under the radio-outage profile from a cold start (a
  //   first catch travels 0.4 m): 196 of 200 caught, 172 with the paper's 0.65 s; the pole's
  //   energy error after the impact 0.002-0.008 J instead of 0.0015-0.004 J (docs/failsafe.md).
  // - retime: this throw's optimal catching instant (42) moves the catch's end for 0.4 s after
  //   the launch, by at most 0.5 m and 0.15 s; 0 s keeps the adapted values (the paper). With
  //   randomised plants a throw's (42) height lay up to 0.7 m from the adapted mean, and a catch
  //   held far below it arrives too fast and drops the pole: at a 0.3 m bound 5 of 49 with seed
  //   2, at 0.5 m 3 (hil fly --throws 50 --randomise, seeds 1-3: 141, then 144 of 147 caught).
  // - missed: the pole's lower end 0.15 m below the catching height, still free, after the
  //   manoeuvre's end (the plate's absorber is 3 cm; the pose noise a few mm).
  CatchSettings catching;
  // The firmware classes an impact within the manoeuvre's remaining time and this margin as a
  // catch, not a crash (which would kill the motors).
  double catch_window_margin_s = 1.0;
  // A catcher whose catch is aborted flies this far sideways, away from where the pole comes down.
  double clear_distance_m = 1.0;
  // When an attempt has launched, is caught or ends (runtime/attempt_phases.hpp): a call to free
  // flight within 0.05 s of the throw's end is the launch; the pole balanced on the catcher for
  // 3 s is caught; the pole's centre below 0.25 m lies on the floor; 15 s after the throw started
  // the attempt ends whatever happens.
  AttemptThresholds attempt;
  // What is learnt from attempt to attempt (adaptation/learner.hpp): the gate against the
  // in-flight prediction (0.2 m, 0.1 s), odd throws (0.5 m, counted from the 3rd in a row), the
  // throw learnt from past trials (gain 0: not learnt).
  adaptation::LearnerSettings learning;
  // The catching instant the learner starts from when (42) finds none for the nominal throw with
  // the configured pole (it finds one for the paper's: 0.812 s after the launch, as the paper
  // measured; this is that, rounded), so that a learner always exists.
  double fallback_catch_instant_s = 0.8;
  // Start from what an earlier run learnt instead of the nominal throw's values.
  std::optional<adaptation::Learnt> learnt;
  // The durable adaptation store (adaptation/adaptation_store.hpp): every throw and every motor
  // identification is recorded there and the adapted values and each vehicle's last accepted
  // identification read back, so that they survive a restart. Empty: in memory only.
  // A store overrides `learnt`; the catching instant is the mean over its history.
  std::string adaptation_store_path;
};

// A task change of one vehicle, for telemetry and logs.
struct MissionEvent {
  double t_s = 0.0;
  pa::VehicleId vehicle{pa::proto::kGroundNode};
  mission::Task from = mission::Task::parked;
  mission::Task to = mission::Task::parked;
  mission::Reason reason = mission::Reason::none;
};

class GroundStation {
 public:
  static constexpr std::size_t kEventLogCapacity = 256;
  // Plans the throw (IPOPT) and designs the controllers: tens of milliseconds.
  // Throws std::runtime_error when the throw cannot be planned, adaptation::StoreError when the
  // adaptation store cannot be opened (the message names the file).
  GroundStation(link::FrameBus& bus, const GroundStationConfig& config = {});

  void on_mocap(const estimation::MocapFrame& frame, double now_s);
  void on_frame(const pa::proto::Frame& frame, double now_s);
  void tick(double now_s);

  // Operator requests.
  void request_take_off() { request_all(mission::condition::request_take_off); }
  void request_land() { request_all(mission::condition::request_land); }
  void request_abort() { request_all(mission::condition::request_abort); }
  // KILL (motors off at once, latched on board) to one vehicle of the act, or to both (nullopt),
  // whatever the mission is doing: never gated. std::out_of_range for a vehicle not of the act.
  void request_kill(std::optional<pa::VehicleId> vehicle, pa::proto::KillReason reason);
  // Starts an attempt; false (and nothing changes, refusal() says why) while one is running, for
  // a vehicle not of the act, when a throw to a target cannot be planned, or when a vehicle's
  // measured thrust gain leaves it short of what its part needs (see min_thrust_margin).
  bool request_attempt(const AttemptRequest& request);
  // Of `preferred` and the other vehicle of the act, the one with the higher thrust ceiling as
  // measured now, `preferred` on a tie (attempt_admission.hpp): the one to throw when either may.
  pa::VehicleId stronger_thrower(pa::VehicleId preferred) const;
  using Refusal = AttemptRefusal;  // runtime/attempt_admission.hpp
  static std::string_view refusal_name(Refusal refusal) { return runtime::refusal_name(refusal); }
  Refusal refusal_kind() const { return refusal_kind_; }
  const std::string& refusal() const { return refusal_; }  // in words, with the numbers

  AttemptPhase attempt_phase() const { return phase_; }
  // Completed attempts, oldest first.
  const std::vector<AttemptReport>& attempts() const { return reports_; }
  const AttemptReport& current_attempt() const { return current_; }
  // The mission events since the last call, oldest first (at most kEventLogCapacity).
  std::vector<MissionEvent> take_events() { return std::exchange(events_, {}); }
  // The vehicles' IMPACT reports since the last call, oldest first (at most kEventLogCapacity).
  std::vector<link::ImpactReport> take_impacts() { return std::exchange(impacts_, {}); }
  // The throw records the adaptation took, oldest first (relative to the throw's origin).
  const std::vector<adaptation::ThrowRecord>& throw_records() const { return learner_.records(); }

  mission::Task task(pa::VehicleId vehicle) const { return vehicle_of(vehicle).sequencer.task(); }
  // The vehicle's thrust gain as measured in flight (1: the airframe file's).
  const estimation::ThrustGainEstimator& thrust_gain(pa::VehicleId vehicle) const {
    return vehicle_of(vehicle).thrust_gain;
  }
  // The vehicle's latest motor identification (none before its first take-off's is over; refused
  // or not), the last accepted one (possibly from the store, an earlier run's), and the lag its
  // firmware's equaliser is set to as far as the ground station knows (acknowledged).
  const std::optional<estimation::IdentificationResult>& motor_identification(pa::VehicleId vehicle) const {
    return vehicle_of(vehicle).motors.identified();
  }
  const std::optional<estimation::MotorIdentification>& kept_motor_identification(
      pa::VehicleId vehicle) const {
    return identifications_.kept(vehicle);
  }
  double equalised_motor_time_constant_s(pa::VehicleId vehicle) const {
    return vehicle_of(vehicle).motors.equalised_s();
  }
  double on_board_inertia_scale(pa::VehicleId vehicle) const {
    return vehicle_of(vehicle).motors.inertia_scale();
  }
  const estimation::StateEstimator& estimator() const { return estimator_; }
  const link::GroundLink& link() const { return link_; }
  const adaptation::AdaptationState& adaptation() const { return learner_.state(); }
  adaptation::Learnt learnt() const { return learner_.learnt(); }
  const GroundStationConfig& config() const { return config_; }
  // The catching height (lower pole end) expected for the next throw, arena frame.
  double catch_height() const;
  // Where and in which direction a vehicle throws (see GroundStationConfig::throw_yaw_rad).
  control::ThrowFrame throw_frame(pa::VehicleId thrower) const;

 private:
  struct Vehicle {
    explicit Vehicle(pa::VehicleId vehicle) : id(vehicle) {}
    pa::VehicleId id;
    mission::VehicleSequencer sequencer;
    TaskState laws;  // target, carrot, integral, take-off ramp
    std::uint32_t requests = 0;
    link::MissionCommands commands;  // ARM, DISARM, LAND, EXPECT_CATCH, CATCH_HANDLED
    double last_pose_s = -1e9;
    estimation::ThrustGainEstimator thrust_gain;
    MotorEqualiser motors;  // each take-off's identification, the lag set on board
    estimation::MocapNoiseMeter noise;
    double pole_trust_s = -1e9;  // when its pole filter's trust was last judged
  };

  // std::out_of_range for a vehicle not of the act.
  const Vehicle& vehicle_of(pa::VehicleId vehicle) const;
  Vehicle& vehicle_of(pa::VehicleId vehicle) {
    return const_cast<Vehicle&>(std::as_const(*this).vehicle_of(vehicle));
  }
  Vehicle& other(const Vehicle& v) { return vehicle_of(pa::other_vehicle(v.id)); }
  void request_all(std::uint32_t request);  // to both vehicles' sequencers
  mission::ConditionFacts facts(const Vehicle& v, double now_s) const;
  void identify_motors(Vehicle& v, double now_s);
  void set_motor_lag(Vehicle& v, double lag_s, double now_s);      // COMMAND set_motor_time_constant
  void set_inertia_scale(Vehicle& v, double scale, double now_s);  // COMMAND set_inertia_scale
  void judge_pole_trust(Vehicle& v);
  void measure_impact_energy(const Vehicle& catcher);
  void send(Vehicle& v, model::VehicleInput u, double now_s);
  // Its motors as the attempt's admission checks them.
  VehicleThrust thrust_of(pa::VehicleId vehicle) const;
  void enter(Vehicle& v, double now_s);
  void fly(Vehicle& v, double now_s, double dt_s);
  void update_attempt(double now_s);
  AttemptFacts attempt_facts(double now_s) const;
  CatchView catch_view(const Vehicle& catcher) const;
  void end_attempt(double now_s);
  // The catch point (lower end, x y) expected for the next throw, arena frame (throw_geometry.hpp).
  Eigen::Vector2d waiting_xy() const;
  std::optional<Eigen::Vector3d> aimed_m() const;  // the target throw's aim, if the attempt has one
  // The catcher's waiting point for the next throw: above the catch point, at the height the z
  // manoeuvre starts from (eq. (49)).
  Eigen::Vector3d waiting_target() const;
  // Where the thrower's centre of gravity hovers before the throw: the throw's origin.
  Eigen::Vector3d throw_origin_target() const;
  // The throw the attempt flies: the one planned to its target, else the Fig. 5 throw.
  const planning::ThrowTrajectory& flown_throw() const;
  const planning::ThrowTracker& flown_tracker() const;

  GroundStationConfig config_;
  link::GroundLink link_;
  estimation::StateEstimator estimator_;
  std::array<Vehicle, 2> vehicles_{Vehicle(pa::kVehicle1), Vehicle(pa::kVehicle2)};  // by pa::act_slot()
  planning::ThrowBook throws_;
  TaskController tasks_;
  adaptation::Learner learner_;
  adaptation::IdentificationMemory identifications_;  // after learner_, which creates the store
  adaptation::CatchEnergyCorrection catch_energy_;
  CatchCoordinator catch_;
  std::vector<MissionEvent> events_;
  std::vector<link::ImpactReport> impacts_;
  // The estimator predicted to when this frame's commands act (latency compensation).
  std::optional<estimation::StateEstimator> ahead_;
  std::optional<double> last_mocap_s_;                   // the last frame's arrival
  std::optional<estimation::MocapPose> last_pole_pose_;  // the pole's latest pose

  // The attempt.
  control::ThrowFrame frame_;  // its thrower's throw frame (the last attempt's when idle)
  AttemptPhase phase_ = AttemptPhase::idle;
  AttemptRequest request_;
  AttemptReport current_;
  std::vector<AttemptReport> reports_;
  int attempt_count_ = 0;
  Refusal refusal_kind_ = Refusal::none;  // why the last request_attempt() was refused
  std::string refusal_;
  std::optional<planning::TargetThrow> target_throw_;  // the attempt's, when it throws to a target
  std::optional<ThrowEnd> throw_end_;                  // the throw's last tracked state near its end
  std::vector<adaptation::TimedPoleState> flight_;     // the pole's, from the launch to the impact
  // The pole's resting end from the plate's centre as the throw started (arena frame).
  Eigen::Vector3d resting_offset_m_ = Eigen::Vector3d::Zero();
  std::optional<double> balanced_since_s_;
  std::optional<double> balanced_on_catcher_s_;
};

}  // namespace gs::runtime
