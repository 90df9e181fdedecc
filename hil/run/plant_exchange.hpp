// The truth plant exchanging frames with firmware on its vehicle buses, one radio per vehicle
// between its bus and the ground bus, and the motion capture: the stepping logic of `hil run`
// (docs/hil.md), whose firmware runs elsewhere (fw_vehicle processes on SocketCAN), and of the
// in-process arena (hil/sil/arena.hpp), which shuttles the frames to the firmware core in memory.
// It reads no clock and touches no socket: the caller hands it the frames it read, asks it to
// step, and writes what it returns.
//
// Time is the plant's: t_k = k ms after k steps. Per vehicle bus, each step sends the new IMU
// sample as HIL_IMU_GYRO and HIL_IMU_ACCEL and waits for the firmware's HIL_MOTORS for that
// sample's tick: answered() says whether every firmware answered, and the caller in lockstep
// steps only then. The answered commands are held over the next step; a sample stepped over
// without its answer (realtime) holds the previous commands, as an ESC holds its last input, and
// counts as missed.
//
// Radios (hil::RadioBridge, each seeded from the exchange's seed: arena_radio_config()):
//  - a frame read on the ground bus is offered to the radio of the vehicle it addresses (both for
//    a broadcast) at t_s(); the step from t_k puts on the vehicle bus, before the sample of
//    t_(k+1), every frame due by t_k;
//  - a frame read on a vehicle bus that a radio carries (all but the HIL exchange) is offered at
//    t_s() and put on the ground bus by the first step that ends at or after its due time.
// Motion capture: the plant's frames, returned by take_mocap() after the step that reached their
// delivery time (capture + the configured mocap latency).
//
// The ground station's lockstep (join_ground_clock()): after every step HIL_CLOCK goes on the
// ground bus, last, with the step and the motion-capture frames delivered so far; the ground
// station runs its own step at that time and answers HIL_CLOCK_DONE, and answered() waits for
// it as for the firmware. So the whole act runs on the plant's time, however slow the machine.
// A ground station that stopped answering (killed) is let go by the caller (release_ground()):
// the plant steps on without it until it answers again (restarted).
//
// The person who hands the pole up (hand_pole_to()), one rule for `hil run` and `hil fly`: asked
// when a throw is accepted, they put the pole upright on the thrower's plate once the ground
// station shows the thrower waiting for it (show_waiting_for_pole()) and it hovers still at the
// throw's origin, where the ground station flies it to wait.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "hil/plant/mocap.hpp"
#include "hil/plant/plant.hpp"
#include "hil/plant/types.hpp"
#include "hil/radio/radio_bridge.hpp"
#include "pa/protocol.hpp"

namespace hil::run {

struct VehicleExchangeCounters {
  std::uint64_t samples_sent = 0;    // IMU samples put on the vehicle bus
  std::uint64_t samples_resent = 0;  // sent again to a firmware that had not answered
  std::uint64_t answered = 0;        // samples whose HIL_MOTORS came back before the next step
  std::uint64_t missed = 0;          // samples stepped over without their answer
  std::uint64_t late_answers = 0;    // HIL_MOTORS for another sample than the one awaited
  std::uint64_t uplink_offered = 0;  // ground frames handed to this vehicle's radio
  std::uint64_t uplink_lost = 0;
  std::uint64_t uplink_delivered = 0;  // put on the vehicle bus
  std::uint64_t downlink_offered = 0;  // vehicle frames handed to the radio
  std::uint64_t downlink_lost = 0;
  std::uint64_t downlink_delivered = 0;  // put on the ground bus
  std::uint64_t not_carried = 0;         // vehicle frames of the HIL exchange other than answers
  std::uint64_t released = 0;            // times the plant stepped on without this firmware
};

struct GroundClockCounters {
  std::uint64_t clocks_sent = 0;    // HIL_CLOCK frames (resent ones included)
  std::uint64_t answered = 0;       // HIL_CLOCK_DONE for the step awaited
  std::uint64_t other_answers = 0;  // for another step (after a resend, or from a late start)
  std::uint64_t released = 0;       // times the plant stepped on without the ground station
};

// What the truth did, per vehicle, for a run's summary.
struct VehicleTruthSummary {
  double highest_m = 0.0;   // the centre's highest z
  double airborne_s = 0.0;  // time with the centre above kAirborneHeight_m
  static constexpr double kAirborneHeight_m = 0.3;
};

class PlantExchange {
 public:
  // The plant from `plant` with external firmware on the first `vehicles` act vehicles (1: vehicle
  // 1 only; 2: both; the other stays parked with its motors off). `radio`'s seed is replaced per
  // vehicle from `seed`, which also seeds the plant. Throws std::invalid_argument for a plant
  // whose IMU is not the firmware's 1 kHz, a vehicle count other than 1 or 2, a bad radio
  // configuration, or whatever the Plant constructor throws.
  PlantExchange(const PlantConfig& plant, const RadioConfig& radio, std::uint64_t seed, std::size_t vehicles);

  const Plant& plant() const { return plant_; }
  // For a caller that moves bodies in the plant between steps (the series' sideways push).
  Plant& plant() { return plant_; }
  double t_s() const { return plant_.t_s(); }
  double period_s() const { return period_s_; }
  std::size_t vehicles() const { return links_.size(); }  // vehicle i (0-based) is node i + 1

  // A frame read from the ground bus now (t_s()).
  void on_ground_frame(const pa::proto::Frame& frame);
  // The radios go silent towards the vehicles from now on: frames in flight and frames sent later
  // never reach them (counted as neither lost nor delivered). The downlink carries on.
  void silence_uplink() { uplink_silent_ = true; }
  // A frame read from `vehicle`'s bus now: its answer to the awaited sample, or a frame for its
  // radio. Frames of a vehicle without firmware here are ignored.
  void on_vehicle_frame(pa::VehicleId vehicle, const pa::proto::Frame& frame);

  // The ground station joins the lockstep: from the next step on, each step waits for its
  // HIL_CLOCK_DONE as well (until release_ground()).
  void join_ground_clock() { ground_clock_ = true; }
  bool ground_clock() const { return ground_clock_; }
  // Whether the ground station is awaited: joined, not released, and its answer to the latest
  // HIL_CLOCK not in.
  bool awaiting_ground() const { return ground_clock_ && !ground_released_ && ground_awaited_.has_value(); }
  // Steps on without the ground station until its next HIL_CLOCK_DONE.
  void release_ground();
  bool ground_released() const { return ground_released_; }
  const GroundClockCounters& ground_clock_counters() const { return ground_counters_; }

  // The pole goes on `thrower`'s plate at the start of the first step that begins with the ground
  // station showing the thrower waiting for it, the plate's centre within kAtOrigin_m of
  // `origin_m` and the vehicle slower than kStillSpeed_mps; a later call replaces the request.
  void hand_pole_to(pa::VehicleId thrower, const Vec3& origin_m);
  // What the ground station shows of `vehicle`: waiting for the pole (hovering, its attempt being
  // prepared) or not; false until said. The caller keeps it up to date.
  void show_waiting_for_pole(pa::VehicleId vehicle, bool waiting);
  std::uint64_t poles_handed() const { return poles_handed_; }
  static constexpr double kAtOrigin_m = 0.1;
  static constexpr double kStillSpeed_mps = 0.2;

  // A firmware that stopped answering (its process killed) is let go: the plant steps on without
  // it, its vehicle's motors stopped (an ESC without input stops), until it answers again.
  void release_vehicle(pa::VehicleId vehicle);
  bool vehicle_released(pa::VehicleId vehicle) const;
  // Whether the plant waits for `vehicle`'s answer to the latest sample.
  bool awaiting_vehicle(pa::VehicleId vehicle) const;
  // Whether `vehicle`'s firmware has answered any sample yet.
  bool vehicle_answered_once(pa::VehicleId vehicle) const;

  // Whether every firmware (and the ground station, joined) answered its latest sample (true
  // before the first step); a released one is not waited for.
  bool answered() const;
  // The latest sample again for each firmware that has not answered it (one started after the
  // sample went out never saw it), into take_vehicle_frames(); the latest HIL_CLOCK again for an
  // awaited ground station, into take_ground_frames().
  void resend_unanswered();

  // One IMU period, t_k -> t_(k+1): uplink frames due by t_k go on the vehicle buses, the pole
  // goes up if the person is ready (hand_pole_to()), the plant steps with the held commands, its new samples go out, the downlink frames due by t_(k+1) go
  // on the ground bus and the motion-capture frames delivered by then are collected.
  void step();

  // What to write on `vehicle`'s bus, in order (radio frames, then the sample's two frames).
  std::vector<pa::proto::Frame> take_vehicle_frames(pa::VehicleId vehicle);
  // What to write on the ground bus, oldest first.
  std::vector<pa::proto::Frame> take_ground_frames();
  // Motion-capture frames delivered since the last call, in capture order.
  std::vector<CapturedFrame> take_mocap();

  // Throws std::out_of_range for a vehicle without firmware here.
  VehicleExchangeCounters counters(pa::VehicleId vehicle) const;
  const VehicleTruthSummary& truth_summary(pa::VehicleId vehicle) const {
    return truth_[pa::act_slot(vehicle)];
  }
  // The commands the plant holds for `vehicle` (all zero: motors off).
  const MotorCommands& motor_commands(pa::VehicleId vehicle) const { return motors_[pa::act_slot(vehicle)]; }
  std::uint64_t ground_frames_not_carried() const { return ground_not_carried_; }

 private:
  struct Link {
    explicit Link(const RadioConfig& config) : bridge(config) {}
    RadioBridge bridge;
    std::vector<pa::proto::Frame> outbox;  // for the vehicle bus
    std::array<pa::proto::Frame, 2> sample{};
    std::optional<std::uint16_t> awaited_tick;  // none: answered (or nothing sent yet)
    bool released = false;
    VehicleExchangeCounters counters;
  };
  Link* link(pa::VehicleId vehicle);

  Plant plant_;
  double period_s_;
  std::vector<Link> links_;  // indexed by pa::act_slot()
  std::array<MotorCommands, 2> motors_{};
  std::array<VehicleTruthSummary, 2> truth_{};
  std::vector<pa::proto::Frame> ground_;
  std::vector<CapturedFrame> mocap_;
  std::uint64_t mocap_delivered_ = 0;
  std::uint64_t steps_ = 0;
  std::uint64_t ground_not_carried_ = 0;
  bool ground_clock_ = false;
  bool ground_released_ = false;
  std::optional<std::uint32_t> ground_awaited_;  // the step whose HIL_CLOCK_DONE is awaited
  GroundClockCounters ground_counters_;
  struct PoleWanted {
    pa::VehicleId thrower;
    Vec3 origin_m;
  };
  std::optional<PoleWanted> pole_for_;
  std::array<bool, 2> waiting_for_pole_{};  // indexed by pa::act_slot()
  std::uint64_t poles_handed_ = 0;
  bool uplink_silent_ = false;
  void send_ground_clock();
  void hand_pole_when_ready();
};

}  // namespace hil::run
