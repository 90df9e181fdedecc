// Processor in the loop (docs/architecture.md "Four ways to run the same code"): one vehicle's
// firmware as the real cross-compiled Cortex-M4 flight image (fw_mps2_an386_pil, built by the
// cortex-m4 preset: firmware/ports/mps2_an386/pil_main.cpp) running in qemu-system-arm, behind
// the same vehicle bus the in-process core has (FirmwareVehicle::on_bus()).
//
// The contract with the image:
//  - QEMU runs `qemu-system-arm -M mps2-an386 -cpu cortex-m4 -nographic -monitor none
//    -icount shift=N -semihosting-config enable=on,target=native -kernel IMAGE
//    -chardev socket,id=pil,path=SOCKET -serial chardev:pil` in a private temporary folder (its
//    working directory), N the image's PA_MPS2_ICOUNT_SHIFT. This process listens on SOCKET, in
//    that folder, before QEMU starts, and QEMU connects to it as a client.
//  - In the folder, `pil_vehicle.cfg`: "PAVC", sizeof(fw::VehicleConfig) as a little-endian u32,
//    then the raw bytes of the fw::VehicleConfig the in-process core would be built from (the
//    image reads it over semihosting at boot).
//  - To the image: the vehicle-bus frames in order, each in the project's serial framing
//    (pa/serial_frame.hpp).
//  - From the image, for every HIL_IMU_GYRO + HIL_IMU_ACCEL pair of its node (one tick): every
//    frame its core sent, then HIL_TICK_COST (what Vehicle::tick cost in guest instructions,
//    exact under -icount), then the tick's HIL_MOTORS, which ends the answer. Frames that run no
//    tick get no answer.
//
// Lockstep: after frames that run a tick, read_answer() waits for every answer, however slow
// QEMU is, so the plant never advances without it and a run is reproducible. A wall-clock
// timeout per answer (EmulatorConfig::answer_timeout_s) ends the run with EmulatedFirmwareError
// naming the tick and carrying QEMU's own output (an image that crashed or hung), never a hang.
// QEMU is killed and waited for when the object is destroyed, and at once on any error; it also
// dies with the thread that started it (PR_SET_PDEATHSIG). The folder is removed once the image
// has answered its first tick (its output stays readable for error messages), so a host killed
// mid-run leaves neither an emulator nor a folder behind. Not copyable: the image's state is in
// its QEMU process.
#pragma once

#include <sys/types.h>
#include <chrono>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "fw/config.hpp"
#include "fw/hil_imu.hpp"
#include "hil/sil/firmware_observation.hpp"
#include "pa/protocol.hpp"
#include "pa/serial_frame.hpp"

namespace hil::sil {

// The -icount shift the PIL image is compiled for (firmware/ports/mps2_an386/CMakeLists.txt's
// PA_MPS2_ICOUNT_SHIFT, read by hil/sil/CMakeLists.txt); none when the build could not read it.
#ifdef PA_PIL_ICOUNT_SHIFT
inline constexpr std::optional<int> kImageIcountShift = PA_PIL_ICOUNT_SHIFT;
#else
inline constexpr std::optional<int> kImageIcountShift = std::nullopt;
#endif

struct EmulatorConfig {
  std::string image;                     // the PIL image (fw_mps2_an386_pil.elf)
  std::string qemu = "qemu-system-arm";  // the emulator, a path or a name looked up in PATH
  // QEMU's -icount shift; it must be the one the image was compiled for (it converts its
  // virtual clock into instructions with it).
  std::optional<int> icount_shift = kImageIcountShift;
  double connect_timeout_s = 10.0;  // for QEMU to start and connect to the socket
  double answer_timeout_s = 10.0;   // for each tick's answer
};

// QEMU could not be started, did not connect, or the image stopped answering.
class EmulatedFirmwareError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class EmulatedFirmware {
 public:
  // Writes `config` for the image, starts QEMU on it and waits for it to connect. Throws
  // std::invalid_argument for a configuration without an image or an icount shift, and
  // EmulatedFirmwareError when QEMU cannot be run or does not connect in time (QEMU's output in
  // the message).
  EmulatedFirmware(const fw::VehicleConfig& config, const EmulatorConfig& emulator);
  ~EmulatedFirmware();
  EmulatedFirmware(const EmulatedFirmware&) = delete;
  EmulatedFirmware& operator=(const EmulatedFirmware&) = delete;

  // Frames on the vehicle bus, in order, written to the image at once (so that several images
  // can run their ticks at the same time); read_answer() collects what they answer.
  void write_bus(const std::vector<pa::proto::Frame>& frames);
  // Waits for the answers to every tick run since the last call and returns them as the core in
  // process sends them: per tick, HIL_MOTORS first, then the core's frames in order (without
  // HIL_TICK_COST, kept in last_tick_instructions()). Nothing when no tick ran. Throws
  // EmulatedFirmwareError when an answer does not come within the timeout or QEMU closes the
  // line (QEMU is killed then, and every later call throws).
  std::vector<pa::proto::Frame> read_answer();
  std::vector<pa::proto::Frame> on_bus(const std::vector<pa::proto::Frame>& frames) {
    write_bus(frames);
    return read_answer();
  }

  // What the latest answered tick cost in guest instructions (none before the first tick, or
  // when its answer carried no HIL_TICK_COST).
  std::optional<std::uint32_t> last_tick_instructions() const { return last_tick_instructions_; }
  std::uint64_t ticks_answered() const { return ticks_answered_; }

  // The firmware as its frames show it: mode and failsafe reason from its latest
  // VEHICLE_HEARTBEAT, impact count from its latest TELEMETRY_STATUS, setpoint from the latest
  // RATE_THRUST for its node it was handed (handed, not necessarily accepted: the image's link
  // guard may still refuse it).
  const FirmwareObservation& observe() const { return observed_; }
  // How old that setpoint is at `now_us` on the firmware's clock (kNoSetpoint before the first);
  // it is stamped with the firmware's clock when handed (the time of the last IMU sample before it).
  std::uint32_t setpoint_age_us(std::uint32_t now_us) const;

  std::uint8_t node() const { return node_; }
  pid_t qemu_pid() const { return pid_; }
  // QEMU's working directory; empty once removed (after the first answer).
  const std::string& folder() const { return folder_; }
  // The serial framing's counters of what the image sent (CRC and header errors).
  const pa::serial_frame::DecoderStats& decoder_stats() const { return decoder_.stats(); }

 private:
  [[noreturn]] void fail(const std::string& what);
  void stop();                      // kills QEMU (if running), waits for it, closes the sockets
  std::string qemu_output() const;  // its last lines
  void remove_folder();
  std::string qemu_status(bool wait);
  void spawn(const std::vector<std::string>& args);
  void accept_connection(double timeout_s);
  void write_bytes(const std::uint8_t* data, std::size_t size);
  void observe_handed(const pa::proto::Frame& frame);
  void observe_sent(const pa::proto::Frame& frame);

  std::uint8_t node_;
  EmulatorConfig emulator_;
  std::string folder_;
  std::string log_path_;
  pid_t pid_ = -1;
  int exit_status_ = -1;  // waitpid's status once reaped
  int log_fd_ = -1;       // QEMU's output file, open for reading
  int listen_fd_ = -1;
  int fd_ = -1;
  bool failed_ = false;
  std::string failure_;

  fw::HilImuAssembler imu_{};   // the image's, mirrored: which frames run a tick
  std::uint32_t clock_us_ = 0;  // the firmware's clock: its last sample's time
  std::uint32_t ticks_awaited_ = 0;
  std::uint16_t tick_awaited_ = 0;  // the latest tick sent, for messages
  pa::serial_frame::Decoder decoder_;
  std::vector<pa::proto::Frame> pending_;  // frames of a tick whose HIL_MOTORS is not in yet
  std::optional<std::uint32_t> pending_cost_;
  std::optional<std::uint32_t> last_tick_instructions_;
  std::uint64_t ticks_answered_ = 0;

  FirmwareObservation observed_{};
  bool has_setpoint_ = false;
  std::uint32_t setpoint_us_ = 0;
};

}  // namespace hil::sil
