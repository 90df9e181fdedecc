// The arena in lockstep: the truth plant, both vehicles flown by the real firmware core
// (FirmwareVehicle), one radio per vehicle between the ground CAN bus and that vehicle's bus
// (hil::RadioBridge) and the motion capture with its latency, stepped together one IMU period
// at a time, reproducible from one seed, without a wall clock. The plant, the radios, their
// counters and the person who hands the pole up are `hil run`'s (hil::run::PlantExchange); the
// arena shuttles the frames on each vehicle bus between it and the firmware core in memory.
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
//    ends at t >= d and after t_(k+1) (a frame due at once, L = J = 0, waits one step, as in
//    `hil run`, where the firmware answers between steps). A COMMAND sent at t_k with J = 0 is
//    thus acknowledged on the ground bus at t_k + 2 L + 1 ms for L >= 1 ms, no earlier.
//  - Motion capture: frame i captures the true poses at i / mocap.rate_Hz (the first at t = 0)
//    and is returned by take_mocap() after the first step that ends at t >= its delivery_t_s
//    (capture + mocap latency + jitter, both from the plant's configuration).
//  - take_ground_frames() and take_mocap() return what arrived since their last call; a caller
//    that steps once between calls sees every arrival within 1 ms of its due time. Nothing is
//    dropped when they are not called: what arrived accumulates.
//
// Seeds: the plant (IMU noise and biases, motion capture) uses the arena's seed itself; each
// radio's seed is derived from it and the vehicle's node (hil::run::arena_radio_config()), so
// the two radios draw distinct, reproducible losses and jitter. Same configuration, seed and
// ground calls: the same frames at the same steps and the same plant states, bit for bit -
// except two fields the firmware fills from the host's clock: TELEMETRY_STATUS's
// tick_time_max_us and overruns (the POSIX port times each tick), which nothing else reads.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "hil/plant/mocap.hpp"
#include "hil/plant/plant.hpp"
#include "hil/radio/radio_bridge.hpp"
#include "hil/run/plant_exchange.hpp"
#include "hil/sil/emulated_firmware.hpp"
#include "hil/sil/firmware_vehicle.hpp"
#include "pa/protocol.hpp"

namespace hil::sil {

struct ArenaConfig {
  // Both vehicles' radios (each seeded from the arena's seed, see above).
  RadioConfig radio{};
  // Which firmware flies the vehicles: none, the core compiled for this host, in process (the
  // default); set, the flight image in QEMU, processor in the loop, one QEMU per vehicle
  // (emulated_firmware.hpp), built from the same configurations. The arena is then as slow as
  // QEMU, steps in the same lockstep, and cannot be copied.
  std::optional<EmulatorConfig> emulated_firmware;
};

class Arena {
 public:
  // The plant from `plant` (used as given: randomise it first if wanted) with firmware built
  // from firmware_config_for(plant.vehicle, node) on both vehicles. Throws
  // std::invalid_argument for a plant whose IMU is not the firmware's 1 kHz, a radio
  // configuration out of range, or whatever the Plant constructor throws.
  Arena(const PlantConfig& plant, const ArenaConfig& config, std::uint64_t seed);
  // With emulated firmware it also throws what EmulatedFirmware's constructor throws (QEMU not
  // started or not connected).
  // A copy carries on from the same state (plant, firmwares, radios, what waits for the ground)
  // and evolves exactly as the original would under the same ground calls: a mission flown once
  // can be forked at any step (hil/trials/cuts.hpp). An arena with emulated firmware cannot be
  // copied (std::logic_error): the images' states are in their QEMU processes.

  Plant& plant() { return exchange_.plant(); }
  const Plant& plant() const { return exchange_.plant(); }

  // The plant's side: the radios' and the HIL exchange's counters per vehicle, the motor commands
  // the plant holds, the ground frames no radio carried.
  const run::PlantExchange& exchange() const { return exchange_; }

  // The firmware of pa::kVehicle1 or pa::kVehicle2; throws std::out_of_range for any other
  // vehicle. What to read of it with either firmware: observe(), setpoint_age_us(), and with
  // emulated firmware last_tick_instructions(), what its latest tick (this step's) cost.
  const FirmwareVehicle& vehicle(pa::VehicleId vehicle) const;
  // Whether the flight images in QEMU fly the vehicles (ArenaConfig::emulated_firmware).
  bool emulated_firmware() const { return firmware_.front().emulated(); }

  double t_s() const { return exchange_.t_s(); }
  double period_s() const { return exchange_.period_s(); }  // 1 ms, the firmware's IMU period

  // A frame the ground station puts on the ground bus now (t_s()). Carried by the radio of the
  // vehicle its identifier's node addresses, by both radios when broadcast (node 15); a frame
  // addressed to any other node (the ground's own 0, vehicles not in the arena) is carried by
  // no radio and counted in exchange().ground_frames_not_carried().
  void send_from_ground(const pa::proto::Frame& frame) { exchange_.on_ground_frame(frame); }

  // The radios go silent towards the vehicles from now on (run::PlantExchange::silence_uplink()).
  void silence_uplink() { exchange_.silence_uplink(); }

  // The person who hands the pole up (run::PlantExchange::hand_pole_to()) and what the ground
  // station shows them (run::PlantExchange::show_waiting_for_pole()).
  void hand_pole_to(pa::VehicleId thrower, const Vec3& origin_m) {
    exchange_.hand_pole_to(thrower, origin_m);
  }
  void show_waiting_for_pole(pa::VehicleId vehicle, bool waiting) {
    exchange_.show_waiting_for_pole(vehicle, waiting);
  }

  // One IMU period, t_k -> t_(k+1): the exchange steps (the radios put on each vehicle bus what
  // is due by t_k, the person hands the pole up if ready, the plant steps, its new IMU samples go
  // on the vehicle buses, the downlink and motion-capture frames due by t_(k+1) are collected for
  // the ground), then each firmware reads its bus, runs its tick and answers; what it sent is
  // offered to its radio at t_(k+1). Emulated firmware: both images get their buses before
  // either answer is awaited, so they run their ticks at the same time; EmulatedFirmwareError
  // when one does not answer.
  void step();

  // Frames that arrived on the ground bus since the last call, oldest first (within one step,
  // node 1's radio before node 2's).
  std::vector<pa::proto::Frame> take_ground_frames() { return exchange_.take_ground_frames(); }
  // Motion-capture frames delivered since the last call, in capture order.
  std::vector<CapturedFrame> take_mocap() { return exchange_.take_mocap(); }

 private:
  run::PlantExchange exchange_;
  std::vector<FirmwareVehicle> firmware_;  // indexed by pa::act_slot()
};

}  // namespace hil::sil
