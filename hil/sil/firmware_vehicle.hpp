// In-process software-in-the-loop (docs/architecture.md "Four ways to run the same code"): a truth
// plant vehicle flown by the real firmware core through the same HIL port the SocketCAN process
// uses (fw::posix::HilVehicleNode), in lockstep and without a wall clock.
//
// The coupling is the vehicle bus of the HIL, in memory: each plant IMU sample goes to the
// firmware as HIL_IMU_GYRO and HIL_IMU_ACCEL frames (so the sample is quantised exactly as on the
// bus), every tenth after the battery's HIL_BATTERY (hil_frames.hpp), the firmware answers with HIL_MOTORS for the same tick, and those motor commands are
// held over the plant's next step. The plant is the time master: the firmware's clock is the
// plant's IMU tick (tick k = k ms), so a run is reproducible from the plant's seed.
//
// Timing of one step, k -> k + 1: the plant integrates over the step with the commands answered
// to sample k, ends with sample k + 1 at (k + 1) ms, the ground frames queued since the last
// step reach the firmware (read at vehicle time k ms, the clock of its last sample), then sample
// k + 1 runs the firmware's tick and its HIL_MOTORS answer is what the plant holds next. The
// firmware's computation thus costs one IMU period of transport delay, the most a 1 kHz loop
// that answers within its tick can cost.
//
// Ground-to-vehicle frames go straight to the vehicle's bus here (inject()). The arena
// (arena.hpp) instead hands the firmware its whole vehicle bus as hil::run::PlantExchange writes
// it (on_bus()): radio frames, the IMU sample and back the answer, on the same frames.
//
// The same vehicle bus also reaches the real flight image in QEMU, processor in the loop
// (emulated_firmware.hpp): a FirmwareVehicle built with an EmulatorConfig runs its firmware
// there instead of in process, in the same lockstep and with the same answers; it has no
// fw::Vehicle here (firmware() throws), so what callers read of either is observe().
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "fw/config.hpp"
#include "hil/plant/plant.hpp"
#include "hil/sil/emulated_firmware.hpp"
#include "hil/sil/firmware_observation.hpp"
#include "hil_vehicle_node.hpp"
#include "pa/protocol.hpp"

namespace hil::sil {

// The firmware configuration for the airframe the plant's NOMINAL vehicle describes, so that
// the firmware's model (rate loop inertia, mixer geometry and thrust range, impact detector's
// motor lag) and the plant start from the same numbers: mass, principal inertia, arm length,
// yaw moment per thrust, the maximum motor thrust (so that a HIL_MOTORS command of 1 asks for
// the same newtons on both sides) and the motor time constant. Everything else keeps the
// firmware's documented defaults (fw/config.hpp), in particular motor_thrust_min_N, the ESC's
// armed idle, which the plant has no parameter for: the plant turns its command into thrust
// linearly from zero.
// The plant's per-motor gains, drag and randomised parameters are deliberately not passed on:
// they are what the firmware has to cope with (randomise the plant after building this).
// The battery's reference voltage (the plant's battery_reference_voltage_V, where the maximum
// motor thrust is made) is the firmware's too, so that its compensation turns the plant's
// HIL_BATTERY voltage into the factor the plant's motor law asks for.
// It carries the vehicle's simulation_key() and a session nonce of 1.
fw::VehicleConfig firmware_config_for(
    const VehicleConfig& plant_vehicle, pa::VehicleId vehicle,
    double battery_reference_voltage_V = BatteryConfig{}.reference_voltage_V);

// A vehicle's link key in simulation (pa/link_auth.hpp): fixed and public, so a simulated ground
// station and its simulated vehicles agree. Real vehicles get theirs at flashing time.
pa::auth::Key simulation_key(pa::VehicleId vehicle);

// One plant vehicle flown by one firmware core: in process, or the flight image in QEMU.
class FirmwareVehicle {
 public:
  // Flies the plant vehicle `config.link.vehicle` is with the core in process; throws
  // std::invalid_argument for a vehicle other than pa::kVehicle1 and pa::kVehicle2.
  explicit FirmwareVehicle(const fw::VehicleConfig& config);
  // The same with the flight image in QEMU, built from the same `config` (EmulatedFirmware's
  // constructor throws what it throws).
  FirmwareVehicle(const fw::VehicleConfig& config, const EmulatorConfig& emulator);
  // An in-process vehicle copies (the arena forks missions so, hil/trials/cuts.hpp); copying an
  // emulated one throws std::logic_error: its state is in its QEMU process, which is not shared.
  FirmwareVehicle(const FirmwareVehicle&) = default;
  FirmwareVehicle& operator=(const FirmwareVehicle&) = default;
  FirmwareVehicle(FirmwareVehicle&&) noexcept = default;
  FirmwareVehicle& operator=(FirmwareVehicle&&) noexcept = default;
  ~FirmwareVehicle() = default;

  // Whether the firmware is the flight image in QEMU.
  bool emulated() const { return static_cast<bool>(emulated_.image); }

  pa::VehicleId vehicle() const { return vehicle_; }

  // A frame from the ground side (COMMAND, GS_HEARTBEAT, RATE_THRUST, KILL, TIMESYNC_REQUEST...),
  // put on the vehicle bus before the next IMU sample (the firmware reads it then).
  void inject(const pa::proto::Frame& frame) { inbox_.push_back(frame); }

  // Hand the firmware the plant's IMU sample: the queued ground frames, then the sample as two
  // HIL_IMU frames; decodes the HIL_MOTORS answer into motor_commands(). If the firmware does
  // not answer for this tick (it always should in process), the previous commands are held, as
  // an ESC holds its last input, and missed_ticks() counts it.
  void on_imu(const ImuSample& sample);

  // What the plant holds over its next step: the firmware's normalised commands, 0..1 per motor
  // in the firmware's motor order (the plant's order too, types.hpp).
  const MotorCommands& motor_commands() const { return motors_; }

  // Every frame the firmware sent except HIL_MOTORS (heartbeats, telemetry, acks, IMPACT...),
  // oldest first, since the last call.
  std::vector<pa::proto::Frame> take_sent();

  // Frames on the vehicle bus, read by the firmware in order (a HIL_IMU pair runs its tick);
  // returns every frame it sent meanwhile, HIL_MOTORS included, oldest first. Beside the
  // inject() / on_imu() / take_sent() path, whose counters and motor commands it leaves alone.
  std::vector<pa::proto::Frame> on_bus(const std::vector<pa::proto::Frame>& frames);
  // on_bus() in two halves, so that the arena lets every emulated image run its tick at the same
  // time: write_bus() hands the frames over (in process: runs them), read_answer() returns what
  // on_bus() would have (emulated: waits for it, EmulatedFirmwareError when it does not come).
  void write_bus(const std::vector<pa::proto::Frame>& frames);
  std::vector<pa::proto::Frame> read_answer();

  // The firmware itself, read only (mode, failsafe reason, attitude estimate...); in process
  // only: throws std::logic_error for the emulated image.
  const fw::Vehicle& firmware() const;
  // Mode, failsafe reason, impact count and setpoint: in process the core's own, emulated what
  // its frames say (EmulatedFirmware::observe()).
  FirmwareObservation observe() const;
  // How old the latest setpoint is at `now_us` on the firmware's clock (kNoSetpoint before the
  // first): fw::CommandLink::setpoint_age_us() in process, EmulatedFirmware's otherwise.
  std::uint32_t setpoint_age_us(std::uint32_t now_us) const;
  // What the latest tick cost the emulated image in guest instructions (HIL_TICK_COST); none
  // in process.
  std::optional<std::uint32_t> last_tick_instructions() const;

  std::uint64_t samples_fed() const { return samples_fed_; }
  std::uint64_t missed_ticks() const { return missed_ticks_; }

 private:
  // The emulated image, if any: copying it is refused, not shared.
  struct Emulated {
    Emulated() = default;
    Emulated(const Emulated& other);
    Emulated& operator=(const Emulated& other);
    Emulated(Emulated&&) noexcept = default;
    Emulated& operator=(Emulated&&) noexcept = default;
    ~Emulated() = default;
    std::unique_ptr<EmulatedFirmware> image;
  };

  pa::VehicleId vehicle_;
  std::uint8_t node_;                                   // vehicle_'s, on the wire
  std::optional<fw::posix::HilVehicleNode> node_impl_;  // in process
  Emulated emulated_;
  std::vector<pa::proto::Frame> answer_;  // in process: written, not read yet
  std::vector<pa::proto::Frame> inbox_;
  std::vector<pa::proto::Frame> sent_;
  MotorCommands motors_{};
  std::uint64_t samples_fed_ = 0;
  std::uint64_t missed_ticks_ = 0;
};

// The plant and up to one firmware per plant vehicle, stepped together one IMU period at a time,
// without radios (the arena, arena.hpp, steps through `hil run`'s plant exchange instead). A plant
// vehicle without firmware gets zero motor commands (it stays parked, or falls), and its
// IMU samples are discarded so that the plant's queue does not grow.
class Lockstep {
 public:
  // The plant's IMU must run at the firmware's 1 kHz (pa::kImuRate_Hz): the firmware's clock is
  // the HIL_IMU tick count times 1 ms. Throws std::invalid_argument otherwise (and whatever the
  // Plant constructor throws).
  Lockstep(const PlantConfig& config, std::uint64_t seed);

  Plant& plant() { return plant_; }
  const Plant& plant() const { return plant_; }

  // Fly plant vehicle `config.link.vehicle` with a firmware built from `config`; replaces any
  // firmware already there (std::invalid_argument for a vehicle the plant does not have). The
  // firmware receives its first sample at the next step().
  FirmwareVehicle& attach_firmware(const fw::VehicleConfig& config);
  // The firmware flying `vehicle`, or nullptr.
  FirmwareVehicle* firmware(pa::VehicleId vehicle);

  // One IMU period: the plant advances with the held commands, then each firmware gets the new
  // sample and answers with the commands for the following period.
  void step();

  double t_s() const { return plant_.t_s(); }
  double period_s() const { return period_s_; }

 private:
  Plant plant_;
  double period_s_;
  std::array<std::optional<FirmwareVehicle>, 2> firmware_;
};

}  // namespace hil::sil
