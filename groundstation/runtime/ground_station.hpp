// The ground-station runtime: the one object that flies the mission, as a loop over named
// pieces. It owns the estimator, the link, both vehicles (act_vehicle.hpp), the task
// controllers, the throw book, the learner and the attempt (attempt_runner.hpp), and is driven
// from outside by three calls and nothing else:
//   on_mocap(frame, now)  a motion-capture frame arrived: the laws' time step
//                        (frame_interval.hpp), estimator update, each vehicle's pose to its
//                        adaptation (vehicle_adaptation.hpp), the attempt's step
//                        (attempt_runner.hpp), then for each vehicle its condition facts and word
//                        (condition_facts.hpp), its sequencer step, the new task's entry actions
//                        (task_entry.hpp) and its task's law (task_control.hpp) to a setpoint,
//                        its thrust over the gain;
//   on_frame(frame, now)  a frame from the vehicles (heartbeats, acks, IMPACT, TIMESYNC),
//                        decoded once by the link, the rates routed to the identification;
//   tick(now)            link housekeeping (heartbeats, retries, TIMESYNC, lost vehicles), the
//                        mission commands (link/mission_commands.hpp), the motors' identification
//                        and the lag and inertia set on board (vehicle_adaptation.hpp).
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
// balances it. The attempt runner admits attempts (attempt_admission.hpp), steps their phases
// (attempt_phases.hpp) and closes them (attempt_close.hpp): throw by throw the learner
// (adaptation/learner.hpp, Section VI) moves the catching height, the waiting point and the
// offset bias.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "groundstation/adaptation/identification_memory.hpp"
#include "groundstation/adaptation/learner.hpp"
#include "groundstation/control/task_laws.hpp"
#include "groundstation/control/throw_frame.hpp"
#include "groundstation/estimation/state_estimator.hpp"
#include "groundstation/estimation/thrust_gain.hpp"
#include "groundstation/link/ground_link.hpp"
#include "groundstation/link/mission_commands.hpp"
#include "groundstation/mission/condition_word.hpp"
#include "groundstation/mission/vehicle_sequencer.hpp"
#include "groundstation/model/vehicle_limits.hpp"
#include "groundstation/planning/throw_book.hpp"
#include "groundstation/runtime/act_vehicle.hpp"
#include "groundstation/runtime/attempt.hpp"
#include "groundstation/runtime/attempt_admission.hpp"
#include "groundstation/runtime/attempt_phases.hpp"
#include "groundstation/runtime/attempt_runner.hpp"
#include "groundstation/runtime/condition_facts.hpp"
#include "groundstation/runtime/frame_interval.hpp"
#include "groundstation/runtime/ground_station_config.hpp"
#include "groundstation/runtime/task_control.hpp"
#include "groundstation/runtime/task_entry.hpp"
#include "groundstation/runtime/vehicle_adaptation.hpp"

namespace gs::runtime {

// A task change of one vehicle, for telemetry and logs.
struct MissionEvent {
  double t_s = 0.0;
  pa::VehicleId vehicle{pa::proto::kGroundNode};
  mission::Task from = mission::Task::parked;
  mission::Task to = mission::Task::parked;
  mission::Reason reason = mission::Reason::none;
  // For a command that failed (arm_failed): the vehicle's answer, "ARM refused: imu_unhealthy".
  std::string why;
};

class GroundStation {
 public:
  static constexpr std::size_t kEventLogCapacity = 256;
  // Plans the throw (IPOPT) and designs the controllers: tens of milliseconds.
  // Throws std::runtime_error when the throw cannot be planned, adaptation::StoreError when the
  // adaptation store cannot be opened (the message names the file).
  GroundStation(link::FrameBus& bus, const GroundStationConfig& config = {});
  GroundStation(const GroundStation&) = delete;  // its pieces hold references to each other
  GroundStation& operator=(const GroundStation&) = delete;

  void on_mocap(const estimation::MocapFrame& frame, double now_s);
  void on_frame(const pa::proto::Frame& frame, double now_s);
  void tick(double now_s);

  // Operator requests.
  void request_take_off() { request_all(mission::condition::request_take_off); }
  void request_land() { request_all(mission::condition::request_land); }
  void request_abort() { request_all(mission::condition::request_abort); }
  // The same for one vehicle of the act (std::out_of_range for another): a pack swap lands one.
  void request_take_off(pa::VehicleId vehicle) {
    vehicle_of(vehicle).requests |= mission::condition::request_take_off;
  }
  void request_land(pa::VehicleId vehicle) {
    vehicle_of(vehicle).requests |= mission::condition::request_land;
  }
  // KILL (motors off at once, latched on board) to one vehicle of the act, or to both (nullopt),
  // whatever the mission is doing: never gated. std::out_of_range for a vehicle not of the act.
  void request_kill(std::optional<pa::VehicleId> vehicle, pa::proto::KillReason reason);
  // Starts an attempt; false (and nothing changes, refusal() says why) while one is running, for
  // a vehicle not of the act, when a throw to a target cannot be planned, when a vehicle's
  // measured thrust leaves it short of what its part needs (GroundStationConfig::
  // min_thrust_fraction), or when the throw would leave the arena's volume (AttemptRunner).
  bool request_attempt(const AttemptRequest& request);
  // Of `preferred` and the other vehicle of the act, the one with the higher thrust ceiling as
  // measured now, `preferred` on a tie (attempt_admission.hpp): the one to throw when either may.
  pa::VehicleId stronger_thrower(pa::VehicleId preferred) const;
  // Whether `vehicle`'s pack no longer gives the Fig. 5 throw its margin
  // (GroundStationConfig::pack_swap): land it and put in a fresh one before it throws.
  bool pack_spent(pa::VehicleId vehicle) const;
  // Its motors as the attempt's admission checks them: thrust gain and reported pack voltage.
  VehicleThrust thrust_of(pa::VehicleId vehicle) const;
  // Its collective thrust at full command as measured now (attempt_admission.hpp).
  double thrust_ceiling_mps2(pa::VehicleId vehicle) const;
  using Refusal = AttemptRefusal;  // runtime/attempt_admission.hpp
  static std::string_view refusal_name(Refusal refusal) { return runtime::refusal_name(refusal); }
  Refusal refusal_kind() const { return attempt_.refusal_kind(); }
  // How often a flying vehicle was found outside the arena's volume and sent to land.
  std::uint64_t volume_breaches() const { return volume_breaches_; }
  const std::string& refusal() const { return attempt_.refusal(); }  // in words, with the numbers

  AttemptPhase attempt_phase() const { return attempt_.phase(); }
  // Completed attempts, oldest first.
  const std::vector<AttemptReport>& attempts() const { return attempt_.reports(); }
  const AttemptReport& current_attempt() const { return attempt_.current(); }
  // The mission events since the last call, oldest first (at most kEventLogCapacity).
  std::vector<MissionEvent> take_events() { return std::exchange(events_, {}); }
  // The vehicles' IMPACT reports since the last call, oldest first (at most kEventLogCapacity).
  std::vector<link::ImpactReport> take_impacts() { return std::exchange(impacts_, {}); }
  // The throw records the adaptation took, oldest first (relative to the throw's origin).
  const std::vector<adaptation::ThrowRecord>& throw_records() const { return learner_.records(); }

  mission::Task task(pa::VehicleId vehicle) const { return vehicle_of(vehicle).sequencer.task(); }
  // Whether `vehicle` waits for a person to put the pole on: the thrower of an attempt being
  // prepared, hovering, its identification flown. The one rule for whoever hands the pole up
  // (the POLE_WANTED event on /pa/events in an arena, the simulated person in-process): a pole put on
  // during an identification stops it or cancels its retry, and the motors stay
  // unequalised (arena envelope campaign seed 2, attempt 893: a 58 ms thrower balanced at 30 ms,
  // dropped the pole onto the catcher, which tumbled).
  bool waiting_for_pole(pa::VehicleId vehicle) const;
  // The vehicle's thrust gain as measured in flight (1: the airframe file's).
  const estimation::ThrustGainEstimator& thrust_gain(pa::VehicleId vehicle) const {
    return vehicle_of(vehicle).adaptation.thrust_gain();
  }
  // The vehicle's latest motor identification (none before its first take-off's is over; refused
  // or not), the last accepted one (possibly from the store, an earlier run's), and the lag its
  // firmware's equaliser is set to as far as the ground station knows (acknowledged).
  const std::optional<estimation::IdentificationResult>& motor_identification(pa::VehicleId vehicle) const {
    return vehicle_of(vehicle).adaptation.motors().identified();
  }
  const std::optional<estimation::MotorIdentification>& kept_motor_identification(
      pa::VehicleId vehicle) const {
    return identifications_.kept(vehicle);
  }
  double equalised_motor_time_constant_s(pa::VehicleId vehicle) const {
    return vehicle_of(vehicle).adaptation.motors().equalised_s();
  }
  double on_board_inertia_scale(pa::VehicleId vehicle) const {
    return vehicle_of(vehicle).adaptation.motors().inertia_scale();
  }
  const estimation::StateEstimator& estimator() const { return estimator_; }
  const link::GroundLink& link() const { return link_; }
  const adaptation::AdaptationState& adaptation() const { return learner_.state(); }
  adaptation::Learnt learnt() const { return learner_.learnt(); }
  // The Fig. 5 throw this ground station flies, for others of its configuration to share.
  const std::shared_ptr<const planning::Fig5Throw>& fig5_throw() const { return throws_.fig5(); }
  const GroundStationConfig& config() const { return config_; }
  // The catching height (lower pole end) expected for the next throw, arena frame.
  double catch_height() const { return attempt_.catch_height(); }
  // Where and in which direction a vehicle throws (see GroundStationConfig::throw_yaw_rad).
  control::ThrowFrame throw_frame(pa::VehicleId thrower) const;

 private:
  // std::out_of_range for a vehicle not of the act.
  const ActVehicle& vehicle_of(pa::VehicleId vehicle) const;
  ActVehicle& vehicle_of(pa::VehicleId vehicle) {
    return const_cast<ActVehicle&>(std::as_const(*this).vehicle_of(vehicle));
  }
  void request_all(std::uint32_t request);  // to both vehicles' sequencers
  mission::ConditionFacts facts(const ActVehicle& v, double now_s) const;
  void set_on_board(ActVehicle& v, const std::vector<OnBoardCommand>& commands, double now_s);
  void correct_onboard_tilt(ActVehicle& v, const pa::proto::TelemetryAttitude& attitude, double now_s);
  void keep_inside_volume(ActVehicle& v);
  void send(ActVehicle& v, const model::VehicleInput& u, double now_s);
  void enter(ActVehicle& v, double now_s);
  void fly(ActVehicle& v, double now_s, double dt_s);

  GroundStationConfig config_;
  link::GroundLink link_;
  estimation::StateEstimator estimator_;
  planning::ThrowBook throws_;
  TaskController tasks_;
  adaptation::Learner learner_;
  adaptation::IdentificationMemory identifications_;  // after learner_, which creates the store
  AttemptRunner attempt_;                             // after what it reads: estimator_, learner_, throws_
  ActVehicles vehicles_;
  std::vector<MissionEvent> events_;
  std::vector<link::ImpactReport> impacts_;
  // The estimator predicted to when this frame's commands act (latency compensation).
  std::optional<estimation::StateEstimator> ahead_;
  std::optional<double> last_mocap_s_;  // the last frame's arrival
  std::uint64_t volume_breaches_ = 0;
};

}  // namespace gs::runtime
