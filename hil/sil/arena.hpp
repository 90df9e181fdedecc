// The arena in lockstep: the truth plant, both vehicles flown by the real firmware core
// (Lockstep), one radio per vehicle between the ground CAN bus and that vehicle's bus
// (hil::RadioBridge) and the motion capture with its latency, stepped together one IMU period
// at a time, reproducible from one seed, without a wall clock.
//
// The ground station is not in it. The arena's face to the ground is what a ground station in
// the arena sees: the ground bus (frames in with send_from_ground(), frames out with
// take_ground_frames()) and the motion-capture frames (take_mocap()).
//
// Timing contract. Arena time is the plant's: t_k = k ms after k steps. Ground-side calls are
// made between steps, at the current t_s(). L is RadioConfig::latency_s, J its jitter_s, and a
// time within 1 ns of the millisecond grid counts as on it.
//  - Uplink: a frame sent at t is due on the vehicle bus at d = t + L + U(0, J), never before
//    the frame sent before it on the same radio (a radio delivers in order). The step from t_k
//    begins by putting on the vehicle bus every frame due by t_k, so the frame is read by the
//    firmware at its clock t_k for the first t_k >= d (the firmware's clock is its last IMU
//    sample). With J = 0, a frame sent at t_k is read at t_k + L.
//  - The firmware acts on what it read in its tick for the next sample, t_k + 1 ms (a COMMAND
//    is executed and acknowledged there, a setpoint flown from there).
//  - Downlink: every frame the firmware sends in the step t_k -> t_(k+1) (except HIL_MOTORS,
//    which is the plant's) is offered to its radio at t_(k+1), due on the ground bus at
//    d = t_(k+1) + L + U(0, J), and returned by take_ground_frames() after the first step that
//    ends at t >= d. A COMMAND sent at t_k with J = 0 is thus acknowledged on the ground bus at
//    t_k + 2 L + 1 ms, no earlier.
//  - Motion capture: frame i captures the true poses at i / mocap.rate_Hz (the first at t = 0)
//    and is returned by take_mocap() after the first step that ends at t >= its delivery_t_s
//    (capture + mocap latency + jitter, both from the plant's configuration).
//  - take_ground_frames() and take_mocap() return what arrived since their last call; a caller
//    that steps once between calls sees every arrival within 1 ms of its due time. Nothing is
//    dropped when they are not called: what arrived accumulates.
//
// Seeds: the plant (IMU noise and biases, motion capture) uses the arena's seed itself; each
// radio's seed is derived from it and the vehicle's node (RadioConfig::seed is not used), so
// the two radios draw distinct, reproducible losses and jitter. Same configuration, seed and
// ground calls: the same frames at the same steps and the same plant states, bit for bit -
// except two fields the firmware fills from the host's clock: TELEMETRY_STATUS's
// tick_time_max_us and overruns (the POSIX port times each tick), which nothing else reads.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "hil/plant/mocap.hpp"
#include "hil/plant/plant.hpp"
#include "hil/radio/radio_bridge.hpp"
#include "hil/sil/firmware_vehicle.hpp"
#include "pa/protocol.hpp"

namespace hil::sil {

struct ArenaConfig {
  // Both vehicles' radios (each seeded from the arena's seed, see above).
  RadioConfig radio{};
};

// `radio` losing frames as `plant` says (radio_loss_probability, radio_outage_s): how every trial
// configures its radios from its plant (hil/trials/trial_config.hpp).
RadioConfig with_plant_losses(RadioConfig radio, const PlantConfig& plant);

// An arena vehicle's radio: `radio` with its seed derived from the arena's seed and the vehicle's
// node (see "Seeds" above). `hil run` seeds its radios the same way.
RadioConfig arena_radio_config(RadioConfig radio, std::uint64_t arena_seed, pa::VehicleId vehicle);

// Which act vehicles' radios carry a frame put on the ground bus, indexed by pa::act_slot(): the
// vehicle its identifier addresses, both for a broadcast (node 15), none for any other node.
std::array<bool, 2> radios_carrying(const pa::proto::Frame& frame);

// What one vehicle's radio did, per direction (up = ground -> vehicle).
struct RadioCounters {
  std::uint64_t uplink_offered = 0;  // frames handed to the radio on the ground bus
  std::uint64_t uplink_lost = 0;
  std::uint64_t uplink_delivered = 0;  // put on the vehicle bus
  std::uint64_t downlink_offered = 0;  // frames the firmware sent
  std::uint64_t downlink_lost = 0;
  std::uint64_t downlink_delivered = 0;  // put on the ground bus
};

class Arena {
 public:
  // The plant from `plant` (used as given: randomise it first if wanted) with firmware built
  // from firmware_config_for(plant.vehicle, node) on both vehicles. Throws
  // std::invalid_argument for a plant whose IMU is not the firmware's 1 kHz, a radio
  // configuration out of range, or whatever the Plant constructor throws.
  Arena(const PlantConfig& plant, const ArenaConfig& config, std::uint64_t seed);
  // A copy carries on from the same state (plant, firmwares, radios, what waits for the ground)
  // and evolves exactly as the original would under the same ground calls: a mission flown once
  // can be forked at any step (hil/trials/cuts.hpp). Not assigned or moved: it points into its own
  // Lockstep.
  Arena(const Arena& other);
  Arena& operator=(const Arena&) = delete;

  Plant& plant() { return lockstep_.plant(); }
  const Plant& plant() const { return lockstep_.plant(); }

  // The firmware of pa::kVehicle1 or pa::kVehicle2; throws std::out_of_range for any other
  // vehicle. Its inject() bypasses the radio.
  FirmwareVehicle& vehicle(pa::VehicleId vehicle);
  const FirmwareVehicle& vehicle(pa::VehicleId vehicle) const;

  double t_s() const { return lockstep_.t_s(); }
  double period_s() const { return lockstep_.period_s(); }  // 1 ms, the firmware's IMU period

  // A frame the ground station puts on the ground bus now (t_s()). Carried by the radio of the
  // vehicle its identifier's node addresses, by both radios when broadcast (node 15); a frame
  // addressed to any other node (the ground's own 0, vehicles not in the arena) is carried by
  // no radio and counted in not_carried().
  void send_from_ground(const pa::proto::Frame& frame);

  // The radio goes silent towards the vehicles from now on: frames in flight and frames sent
  // later never reach them (counted as neither lost nor delivered). The downlink carries on.
  void silence_uplink() { uplink_silent_ = true; }

  // One IMU period, t_k -> t_(k+1): the radios put on each vehicle bus what is due by t_k, the
  // plant and both firmwares step (Lockstep::step()), the frames the firmwares sent are offered
  // to their radios at t_(k+1), then the downlink frames and motion-capture frames due by
  // t_(k+1) are collected for the ground.
  void step();

  // Frames that arrived on the ground bus since the last call, oldest first (within one step,
  // node 1's radio before node 2's).
  std::vector<pa::proto::Frame> take_ground_frames();
  // Motion-capture frames delivered since the last call, in capture order.
  std::vector<MocapFrame> take_mocap();

  // The radio of pa::kVehicle1 or pa::kVehicle2; throws std::out_of_range for any other vehicle.
  RadioCounters radio(pa::VehicleId vehicle) const;
  // Ground frames addressed to no arena vehicle.
  std::uint64_t not_carried() const { return not_carried_; }

 private:
  struct Link {
    explicit Link(const RadioConfig& config) : bridge(config) {}
    RadioBridge bridge;
    std::uint64_t uplink_delivered = 0;
    std::uint64_t downlink_delivered = 0;
  };
  static std::size_t slot(pa::VehicleId vehicle);  // throws std::out_of_range

  Lockstep lockstep_;
  std::array<FirmwareVehicle*, 2> vehicles_{};  // owned by lockstep_, indexed by pa::act_slot()
  std::vector<Link> links_;                     // indexed by pa::act_slot()
  std::vector<pa::proto::Frame> ground_;
  std::vector<MocapFrame> mocap_;
  std::uint64_t not_carried_ = 0;
  bool uplink_silent_ = false;
};

}  // namespace hil::sil
