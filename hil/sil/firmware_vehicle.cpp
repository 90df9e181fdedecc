#include "hil/sil/firmware_vehicle.hpp"

#include <stdexcept>
#include <string>
#include <utility>

#include "hil/run/hil_frames.hpp"
#include "pa/constants.hpp"

namespace hil::sil {

using pa::proto::Frame;
using run::hil_imu_frames;
using run::hil_tick;
using run::hil_battery_frame;
using run::MotorsAnswer;
using run::read_hil_motors;

fw::VehicleConfig firmware_config_for(const VehicleConfig& plant_vehicle, pa::VehicleId vehicle,
                                      double battery_reference_voltage_V) {
  fw::VehicleConfig c{};
  fw::AirframeConfig& a = c.airframe;
  a.mass_kg = static_cast<float>(plant_vehicle.mass_kg);
  a.inertia_kgm2[0] = static_cast<float>(plant_vehicle.inertia_xx_kgm2);
  a.inertia_kgm2[1] = static_cast<float>(plant_vehicle.inertia_yy_kgm2);
  a.inertia_kgm2[2] = static_cast<float>(plant_vehicle.inertia_zz_kgm2);
  // Both sides put the motors on the diagonals at this distance from the centre (mixer.hpp,
  // motor.hpp), in the same order and with the same spin directions.
  a.arm_length_m = static_cast<float>(plant_vehicle.arm_length_m);
  a.yaw_moment_per_thrust_m = static_cast<float>(plant_vehicle.yaw_moment_per_thrust_m);
  // The mixer sends thrust / motor_thrust_max_N; the plant makes command * gain *
  // motor_thrust_max_N of it. With the same maximum the command is a thrust fraction on both
  // sides, and only the plant's (unknown to the firmware) gains differ.
  a.motor_thrust_max_N = static_cast<float>(plant_vehicle.motor_thrust_max_N);
  a.motor_time_constant_s = static_cast<float>(plant_vehicle.motor_time_constant_s);
  // The voltage at which motor_thrust_max_N is made: the firmware scales its commands by
  // (V_ref / V)^2 from the HIL_BATTERY voltage (fw/battery_compensation.hpp).
  c.battery.reference_voltage_V = static_cast<float>(battery_reference_voltage_V);
  c.link.vehicle = vehicle;
  c.link.key = simulation_key(vehicle);
  c.link.session_nonce = 1;
  return c;
}

pa::auth::Key simulation_key(pa::VehicleId vehicle) {
  pa::auth::Key key{};
  for (std::size_t i = 0; i < key.size(); ++i)
    key[i] = static_cast<std::uint8_t>(0xA5u ^ (vehicle.node() * 16u + i));
  return key;
}

FirmwareVehicle::FirmwareVehicle(const fw::VehicleConfig& config)
    : vehicle_(config.link.vehicle), node_(config.link.vehicle.node()), node_impl_(std::in_place, config) {
  if (!pa::is_act_vehicle(vehicle_))
    throw std::invalid_argument("no plant vehicle has node " + std::to_string(node_) + " (1 or 2)");
  inbox_.reserve(16);
  sent_.reserve(64);
}

FirmwareVehicle::FirmwareVehicle(const fw::VehicleConfig& config, const EmulatorConfig& emulator)
    : vehicle_(config.link.vehicle), node_(config.link.vehicle.node()) {
  if (!pa::is_act_vehicle(vehicle_))
    throw std::invalid_argument("no plant vehicle has node " + std::to_string(node_) + " (1 or 2)");
  emulated_.image = std::make_unique<EmulatedFirmware>(config, emulator);
  inbox_.reserve(16);
  sent_.reserve(64);
}

namespace {
[[noreturn]] void refuse_copy() {
  throw std::logic_error(
      "a vehicle flown by its emulated image (QEMU) cannot be copied: the image's state is in its QEMU "
      "process; fork missions (hil cuts) with the firmware in process");
}
}  // namespace

FirmwareVehicle::Emulated::Emulated(const Emulated& other) {
  if (other.image) refuse_copy();
}

FirmwareVehicle::Emulated& FirmwareVehicle::Emulated::operator=(const Emulated& other) {
  if (other.image || image) refuse_copy();
  return *this;
}

const fw::Vehicle& FirmwareVehicle::firmware() const {
  if (!node_impl_)
    throw std::logic_error("vehicle " + std::to_string(node_) +
                           " is flown by its emulated image: no fw::Vehicle in process (read observe())");
  return node_impl_->vehicle();
}

FirmwareObservation FirmwareVehicle::observe() const {
  if (emulated_.image) return emulated_.image->observe();
  const fw::Vehicle& fw = node_impl_->vehicle();
  FirmwareObservation o;
  o.mode = fw.mode();
  o.failsafe_reason = fw.failsafe_reason();
  o.impact_count = fw.impact_count();
  o.setpoint = fw.link().setpoint();
  return o;
}

std::uint32_t FirmwareVehicle::setpoint_age_us(std::uint32_t now_us) const {
  if (emulated_.image) return emulated_.image->setpoint_age_us(now_us);
  return node_impl_->vehicle().link().setpoint_age_us(now_us);
}

std::optional<std::uint32_t> FirmwareVehicle::last_tick_instructions() const {
  if (emulated_.image) return emulated_.image->last_tick_instructions();
  return std::nullopt;
}

void FirmwareVehicle::on_imu(const ImuSample& sample) {
  const std::uint16_t tick = hil_tick(sample);
  std::size_t first_reply = sent_.size();
  if (emulated_.image) {
    // The radio's frames first, then the sample's, as the core's bus has them below.
    for (const Frame& f : hil_imu_frames(sample, node_)) inbox_.push_back(f);
    for (const Frame& f : emulated_.image->on_bus(inbox_)) sent_.push_back(f);
    inbox_.clear();
  } else {
    const auto collect = [this](const Frame& f) { sent_.push_back(f); };
    for (const Frame& f : inbox_) node_impl_->on_frame(f, collect);
    inbox_.clear();
    first_reply = sent_.size();
    for (const Frame& f : hil_imu_frames(sample, node_)) node_impl_->on_frame(f, collect);
  }
  ++samples_fed_;

  // The HIL_MOTORS answer for this tick comes first (hil_vehicle_node.hpp); it is the plant's,
  // not the ground's, so it leaves the collected frames.
  bool answered = false;
  for (std::size_t i = first_reply; i < sent_.size(); ++i) {
    const MotorsAnswer answer = read_hil_motors(sent_[i], node_, tick, motors_);
    if (answer == MotorsAnswer::not_motors) continue;
    if (answer == MotorsAnswer::answer) answered = true;
    sent_.erase(sent_.begin() + static_cast<std::ptrdiff_t>(i));
    --i;
  }
  if (!answered) ++missed_ticks_;
}

std::vector<Frame> FirmwareVehicle::on_bus(const std::vector<Frame>& frames) {
  if (emulated_.image) return emulated_.image->on_bus(frames);
  std::vector<Frame> sent;
  const auto collect = [&sent](const Frame& f) { sent.push_back(f); };
  for (const Frame& f : frames) node_impl_->on_frame(f, collect);
  return sent;
}

void FirmwareVehicle::write_bus(const std::vector<Frame>& frames) {
  if (emulated_.image) {
    emulated_.image->write_bus(frames);
    return;
  }
  const auto collect = [this](const Frame& f) { answer_.push_back(f); };
  for (const Frame& f : frames) node_impl_->on_frame(f, collect);
}

std::vector<Frame> FirmwareVehicle::read_answer() {
  if (emulated_.image) return emulated_.image->read_answer();
  return std::exchange(answer_, {});
}

std::vector<Frame> FirmwareVehicle::take_sent() {
  std::vector<Frame> out;
  out.swap(sent_);
  sent_.reserve(64);
  return out;
}

Lockstep::Lockstep(const PlantConfig& config, std::uint64_t seed)
    : plant_(config, seed), period_s_(1.0 / static_cast<double>(config.imu.rate_Hz)) {
  if (config.imu.rate_Hz != static_cast<int>(pa::kImuRate_Hz))
    throw std::invalid_argument("the firmware runs on a " + std::to_string(pa::kImuRate_Hz) +
                                " Hz IMU; the plant's imu_rate_Hz is " + std::to_string(config.imu.rate_Hz));
}

FirmwareVehicle& Lockstep::attach_firmware(const fw::VehicleConfig& config) {
  const pa::VehicleId vehicle = config.link.vehicle;
  if (!pa::is_act_vehicle(vehicle))
    throw std::invalid_argument("no plant vehicle has node " + std::to_string(vehicle.node()) + " (1 or 2)");
  return firmware_[pa::act_slot(vehicle)].emplace(config);
}

FirmwareVehicle* Lockstep::firmware(pa::VehicleId vehicle) {
  if (!pa::is_act_vehicle(vehicle)) return nullptr;
  auto& slot = firmware_[pa::act_slot(vehicle)];
  return slot ? &*slot : nullptr;
}

void Lockstep::step() {
  const MotorCommands off{};
  const MotorCommands& v1 = firmware_[0] ? firmware_[0]->motor_commands() : off;
  const MotorCommands& v2 = firmware_[1] ? firmware_[1]->motor_commands() : off;
  plant_.step(period_s_, v1, v2);
  for (const pa::VehicleId v : pa::kActVehicles) {
    std::optional<FirmwareVehicle>& firmware = firmware_[pa::act_slot(v)];
    ImuSample sample;
    while (plant_.pop_imu(v, sample)) {
      if (!firmware) continue;
      if (const auto battery = hil_battery_frame(plant_, v, sample)) firmware->inject(*battery);
      firmware->on_imu(sample);
    }
  }
}

}  // namespace hil::sil
