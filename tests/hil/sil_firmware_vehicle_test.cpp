// The first in-process SIL slice: the truth plant's vehicle1 flown by the real firmware core
// (fw::posix::HilVehicleNode over HIL_IMU / HIL_MOTORS frames, hil/sil/firmware_vehicle.hpp).
// A small ground-station stand-in below sends heartbeats, commands and RATE_THRUST setpoints
// the way the protocol table describes; every assertion is on the plant's TRUE state (or on
// what the vehicle reports over the protocol), never on the firmware's own belief.
//
// The plant is plant.yaml as shipped (IMU noise and bias on, one seed), so the firmware meets
// a sensor it does not know the errors of; vehicle2 has no firmware and stays parked.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "fw/failsafe_controller.hpp"
#include "hil/plant/plant_config.hpp"
#include "hil/sil/firmware_vehicle.hpp"

using namespace pa::proto;
using hil::Vec3;

namespace {

constexpr std::uint8_t kNode = pa::kVehicle1.node();  // on the wire
constexpr std::uint16_t kSession = 0x5A17;
constexpr double kG = 9.81;
constexpr std::uint64_t kSeed = 7;

hil::PlantConfig shipped_plant() {
  hil::PlantConfig c{};
  std::string error;
  REQUIRE(hil::load_plant_config(hil::default_plant_config_path(), c, error));
  return c;
}

// The angle between the vehicle's body z-axis and inertial up.
double tilt_rad(const hil::VehicleState& v) {
  const double up = (v.body.attitude * Vec3::UnitZ()).z();
  return std::acos(std::clamp(up, -1.0, 1.0));
}

// The ground station's side of the protocol, just enough to fly: a 50 Hz GS_HEARTBEAT, a
// 200 Hz RATE_THRUST stream (a new sequence number in each frame), commands, and what the
// vehicle says back.
// `compensate`: false flies the firmware without its battery compensation (no reference voltage).
fw::VehicleConfig firmware_for(const hil::PlantConfig& plant, bool compensate) {
  fw::VehicleConfig c =
      hil::sil::firmware_config_for(plant.vehicle, pa::kVehicle1, plant.battery.reference_voltage_V);
  if (!compensate) c.battery.reference_voltage_V = 0.0f;
  return c;
}

class Ground {
 public:
  explicit Ground(const hil::PlantConfig& plant = shipped_plant(), std::uint64_t seed = kSeed,
                  bool compensate = true)
      : rig_(plant, seed), vehicle_(rig_.attach_firmware(firmware_for(rig_.plant().config(), compensate))) {
    signer_.start_session(vehicle_.firmware().guard().nonce(), 0);
  }

  hil::sil::Lockstep& rig() { return rig_; }
  hil::sil::FirmwareVehicle& vehicle() { return vehicle_; }
  const hil::VehicleState& truth() { return rig_.plant().vehicle(pa::kVehicle1); }

  bool heartbeats = true;
  bool streaming = false;
  float thrust_mps2 = 0.0f;
  std::array<float, 3> rate_radps{};

  // One plant tick (1 ms): the ground's periodic frames due now, then the plant and firmware.
  void tick() {
    if (heartbeats && ticks_ % 20 == 0) {
      Frame f;
      if (encode(GsHeartbeat{static_cast<std::uint32_t>(ticks_), kSession, GroundState::active, hb_seq_++},
                 kNode, f))
        send(f);
    }
    if (streaming && ticks_ % 5 == 0) send_setpoint();
    ++ticks_;
    rig_.step();
    for (const Frame& f : vehicle_.take_sent()) read(f);
  }
  void run(double seconds) {
    const long n = std::lround(seconds / rig_.period_s());
    for (long k = 0; k < n; ++k) tick();
  }
  // A setpoint now, outside the 200 Hz grid (for a step at a known instant).
  void send_setpoint() {
    Frame f;
    if (encode(RateThrust{rate_radps, thrust_mps2, static_cast<std::uint8_t>(sp_seq_++ & 0x0Fu)}, kNode, f))
      send(f);
  }
  // A ground frame as the ground station sends it: followed by its AUTH (docs/security.md).
  void send(const Frame& f) {
    Frame auth;
    REQUIRE(signer_.sign(f, auth));
    vehicle_.inject(f);
    vehicle_.inject(auth);
  }
  // Sends the command and runs until its COMMAND_ACK is back (the firmware answers on the next tick).
  CommandAck command(CommandCode code) {
    const std::uint8_t seq = cmd_seq_++;
    Frame f;
    REQUIRE(encode(Command{code, seq, kSession, 0}, kNode, f));
    send(f);
    for (int k = 0; k < 10; ++k) {
      tick();
      if (have_ack_ && last_ack_.seq == seq) return last_ack_;
    }
    FAIL("no COMMAND_ACK for command sequence " << int(seq));
    return {};
  }

  // Modes as VEHICLE_HEARTBEAT reported them, each new one once, with the failsafe reason.
  struct Reported {
    double t_s;
    Mode mode;
    FailsafeReason reason;
  };
  const std::vector<Reported>& modes() const { return modes_; }
  int undecodable() const { return undecodable_; }
  // IMPACT frames as they arrived.
  struct ReportedImpact {
    double t_s;
    Impact impact;
  };
  const std::vector<ReportedImpact>& impacts() const { return impacts_; }

  // The usual start: heartbeats and a zero-thrust stream, ARM, then a climb of about 0.5 m to
  // hover thrust: 1.3 g for 0.5 s, then 0.7 g for 0.455 s, which with the plant's nominal
  // translational drag (k / m = 0.19/s: 1.40 m/s after the first phase) stops the climb.
  void arm() {
    heartbeats = true;
    streaming = true;
    thrust_mps2 = 0.0f;
    rate_radps = {};
    run(0.2);
    REQUIRE(command(CommandCode::arm).result == AckResult::accepted);
    run(0.1);  // armed on the floor, motors idling
  }
  void take_off() {
    thrust_mps2 = static_cast<float>(1.3 * kG);
    run(0.5);
    thrust_mps2 = static_cast<float>(0.7 * kG);
    run(0.455);
    thrust_mps2 = static_cast<float>(kG);
    run(0.1);
    REQUIRE(vehicle_.firmware().mode() == Mode::flying);
    REQUIRE_FALSE(rig_.plant().vehicle_on_floor(pa::kVehicle1));
  }

 private:
  void read(const Frame& f) {
    Message m;
    if (decode(f, m) != DecodeStatus::ok) {
      ++undecodable_;
      return;
    }
    if (m.type == Type::command_ack) {
      last_ack_ = m.command_ack;
      have_ack_ = true;
    } else if (m.type == Type::impact) {
      impacts_.push_back({rig_.t_s(), m.impact});
    } else if (m.type == Type::vehicle_heartbeat) {
      const VehicleHeartbeat& hb = m.vehicle_heartbeat;
      if (modes_.empty() || modes_.back().mode != hb.mode)
        modes_.push_back({rig_.t_s(), hb.mode, hb.failsafe});
    }
  }

  hil::sil::Lockstep rig_;
  hil::sil::FirmwareVehicle& vehicle_;
  pa::auth::Signer signer_{hil::sil::simulation_key(pa::kVehicle1)};
  long ticks_ = 0;
  std::uint8_t hb_seq_ = 0;
  unsigned sp_seq_ = 0;
  std::uint8_t cmd_seq_ = 0;
  CommandAck last_ack_{};
  bool have_ack_ = false;
  int undecodable_ = 0;
  std::vector<Reported> modes_;
  std::vector<ReportedImpact> impacts_;
};

// The body-rate response the firmware's loop should give on an ideal rigid body: the PI law
// torque = J (kp e + I) (fw/rate_controller.hpp), the motors' first-order lag tau, and one IMU
// period of transport delay (the sample averages over the period before it and the answer is
// held over the period after it: about half a period each). The setpoint is 1 for `on_s`, then
// 0; returns the rate at every millisecond from the step (index k: k + 1 ms), integrated finely.
std::vector<double> rate_step_model(double kp, double ki, double tau_s, double delay_s, double on_s,
                                    double total_s) {
  const double h = 1e-5;
  const int per_ms = static_cast<int>(std::lround(1e-3 / h));
  const int delay_steps = static_cast<int>(std::lround(delay_s / h));
  std::vector<double> history(static_cast<std::size_t>(delay_steps) + 1, 0.0);
  std::vector<double> out;
  double w = 0.0, accel = 0.0, integral = 0.0;
  const int n = static_cast<int>(std::lround(total_s / h));
  for (int k = 0; k < n; ++k) {
    const double e = (k * h < on_s ? 1.0 : 0.0) - w;
    const double demand = kp * e + integral;
    integral += ki * e * h;
    history[static_cast<std::size_t>(k % (delay_steps + 1))] = demand;
    const double applied = history[static_cast<std::size_t>((k + 1) % (delay_steps + 1))];  // delay_steps ago
    accel += (applied - accel) * h / tau_s;
    w += accel * h;
    if ((k + 1) % per_ms == 0) out.push_back(w);
  }
  return out;
}

// The first time (s) a response sampled every ms reaches `level`, or -1.
double time_to_reach(const std::vector<double>& w, double level) {
  for (std::size_t k = 0; k < w.size(); ++k)
    if (w[k] >= level) return static_cast<double>(k + 1) * 1e-3;
  return -1.0;
}

}  // namespace

TEST_CASE("the firmware config describes the plant's nominal airframe, and the units agree") {
  hil::VehicleConfig plant{};
  plant.mass_kg = 0.61;
  plant.inertia_xx_kgm2 = 2.1e-3;
  plant.inertia_yy_kgm2 = 2.7e-3;
  plant.inertia_zz_kgm2 = 4.9e-3;
  plant.arm_length_m = 0.2;
  plant.yaw_moment_per_thrust_m = 0.02;
  plant.motor_thrust_max_N = 4.0;
  plant.motor_time_constant_s = 0.025;
  const fw::VehicleConfig c = hil::sil::firmware_config_for(plant, pa::VehicleId(3));
  CHECK(double(c.airframe.mass_kg) == Approx(0.61));
  CHECK(double(c.airframe.inertia_kgm2[0]) == Approx(2.1e-3));
  CHECK(double(c.airframe.inertia_kgm2[1]) == Approx(2.7e-3));
  CHECK(double(c.airframe.inertia_kgm2[2]) == Approx(4.9e-3));
  CHECK(double(c.airframe.arm_length_m) == Approx(0.2));
  CHECK(double(c.airframe.yaw_moment_per_thrust_m) == Approx(0.02));
  CHECK(double(c.airframe.motor_thrust_max_N) == Approx(4.0));
  CHECK(double(c.airframe.motor_time_constant_s) == Approx(0.025));
  CHECK(c.link.vehicle == pa::VehicleId(3));
  // The shipped plant and the firmware's defaults are the same airframe (both cite it).
  const fw::VehicleConfig shipped = hil::sil::firmware_config_for(shipped_plant().vehicle, pa::kVehicle1);
  const fw::AirframeConfig defaults{};
  CHECK(shipped.airframe.mass_kg == defaults.mass_kg);
  CHECK(shipped.airframe.motor_thrust_max_N == defaults.motor_thrust_max_N);
  CHECK(shipped.airframe.motor_time_constant_s == defaults.motor_time_constant_s);
  CHECK(shipped.airframe.arm_length_m == defaults.arm_length_m);

  // A plant with another IMU rate cannot be driven by the 1 kHz firmware.
  hil::PlantConfig slow = shipped_plant();
  slow.imu.rate_Hz = 500;
  CHECK_THROWS_AS(hil::sil::Lockstep(slow, 1), std::invalid_argument);
}

TEST_CASE(
    "SIL: arming needs the documented edge, and a parked vehicle stays down until thrust exceeds hover") {
  Ground ground;
  hil::sil::FirmwareVehicle& v = ground.vehicle();
  const double z0 = ground.truth().body.position_m.z();

  // No ground station yet: the vehicle has no session and refuses.
  ground.heartbeats = false;
  ground.run(0.1);
  CHECK(ground.command(CommandCode::arm).result == AckResult::refused);

  // Heartbeats, but a setpoint asking for thrust: refused for that reason.
  ground.heartbeats = true;
  ground.streaming = true;
  ground.thrust_mps2 = 5.0f;
  ground.run(0.1);
  const CommandAck with_thrust = ground.command(CommandCode::arm);
  CHECK(with_thrust.result == AckResult::refused);
  CHECK(with_thrust.reason == RefuseReason::thrust_not_zero);

  // Zero thrust, but the heartbeat has lapsed (> heartbeat_timeout_us): refused.
  ground.thrust_mps2 = 0.0f;
  ground.heartbeats = false;
  ground.run(fw::SupervisorConfig{}.heartbeat_timeout_us * 1e-6 + 0.05);
  const CommandAck no_heartbeat = ground.command(CommandCode::arm);
  CHECK(no_heartbeat.result == AckResult::refused);
  CHECK(no_heartbeat.reason == RefuseReason::no_ground_heartbeat);
  for (double c : v.motor_commands().command) CHECK(c == 0.0);

  // Zero thrust and a live heartbeat: the disarmed -> armed edge is taken ...
  ground.heartbeats = true;
  ground.run(0.1);
  const CommandAck armed = ground.command(CommandCode::arm);
  CHECK(armed.result == AckResult::accepted);
  CHECK(v.firmware().mode() == Mode::armed);
  // ... once: ARM is an edge, not a level.
  const CommandAck again = ground.command(CommandCode::arm);
  CHECK(again.result == AckResult::refused);
  CHECK(again.reason == RefuseReason::not_disarmed);

  // Armed: the motors idle (fw AirframeConfig::motor_thrust_min_N) and the vehicle stays put.
  ground.run(0.3);
  double idle_N = 0.0;
  for (double f : ground.truth().motor_thrust_N) idle_N += f;
  std::printf("SIL arming: idle thrust %.3f N total (firmware idle 4 x 0.08 N)\n", idle_N);
  CHECK(idle_N == Approx(4 * 0.08).margin(0.03));
  CHECK(ground.rig().plant().vehicle_on_floor(pa::kVehicle1));

  // Flying at 0.8 g (above the take-off threshold, below hover): still on the floor.
  ground.thrust_mps2 = static_cast<float>(0.8 * kG);
  double highest_m = ground.truth().body.position_m.z();
  for (int k = 0; k < 1000; ++k) {
    ground.tick();
    highest_m = std::max(highest_m, ground.truth().body.position_m.z());
    if (!ground.rig().plant().vehicle_on_floor(pa::kVehicle1)) break;
  }
  std::printf("SIL arming: at 0.8 g for 1 s the CG rose %.2f mm\n", (highest_m - z0) * 1e3);
  CHECK(v.firmware().mode() == Mode::flying);
  CHECK(ground.rig().plant().vehicle_on_floor(pa::kVehicle1));
  CHECK(highest_m - z0 < 0.005);

  // 1.2 g: it lifts off, level.
  ground.thrust_mps2 = static_cast<float>(1.2 * kG);
  double liftoff_s = -1.0;
  const double t_cmd = ground.rig().t_s();
  for (int k = 0; k < 500; ++k) {
    ground.tick();
    if (liftoff_s < 0.0 && !ground.rig().plant().vehicle_on_floor(pa::kVehicle1))
      liftoff_s = ground.rig().t_s() - t_cmd;
  }
  const double rise_m = ground.truth().body.position_m.z() - z0;
  std::printf("SIL arming: at 1.2 g off the floor after %.3f s, %.3f m up after 0.5 s, tilt %.2f deg\n",
              liftoff_s, rise_m, tilt_rad(ground.truth()) * 180.0 / M_PI);
  CHECK(liftoff_s > 0.0);
  CHECK(rise_m > 0.1);
  CHECK(tilt_rad(ground.truth()) < 0.05);
  CHECK(v.missed_ticks() == 0);
  CHECK(ground.undecodable() == 0);
}

TEST_CASE("SIL: at hover thrust with zero rates the true vehicle stays level") {
  Ground ground;
  ground.arm();
  ground.take_off();
  const double tilt_start = tilt_rad(ground.truth());
  double tilt_max = tilt_start, rate_max = 0.0;
  const double z_start = ground.truth().body.position_m.z();
  for (int k = 0; k < 1000; ++k) {
    ground.tick();
    tilt_max = std::max(tilt_max, tilt_rad(ground.truth()));
    rate_max = std::max(rate_max, ground.truth().body.rate_body_radps.head<2>().norm());
  }
  const double dz = ground.truth().body.position_m.z() - z_start;
  std::printf(
      "SIL hover: tilt %.3f deg after take-off, at most %.3f deg over 1 s; roll/pitch rate at most %.4f rad/s; "
      "height change %.3f m\n",
      tilt_start * 180.0 / M_PI, tilt_max * 180.0 / M_PI, rate_max, dz);
  // The firmware flies rates only (the ground closes the attitude loop), so the tilt can only
  // drift by the uncorrected rate error: the gyro bias (0.005 rad/s, 1 sigma) over 1 s is a few
  // tenths of a degree. 2 degrees leaves room without hiding a loop that does not hold zero rate.
  CHECK(tilt_max < 2.0 * M_PI / 180.0);
  CHECK(rate_max < 0.05);
  CHECK(ground.vehicle().firmware().mode() == Mode::flying);
  CHECK_FALSE(ground.rig().plant().vehicle_on_floor(pa::kVehicle1));
  CHECK(ground.vehicle().missed_ticks() == 0);
  CHECK(ground.undecodable() == 0);
}

namespace {

// A hover held on the plant's truth (the ground station's job, done here with a PID on height and
// a levelling law on the true attitude) on a battery that drains from full in about 30 s (a
// 40 mAh pack: the plant's battery law at 60 times the speed of the 2.1 Ah one). Returns the
// delivered-over-commanded thrust in the first and last 2 s and the voltage at the end.
struct DischargeHover {
  double ratio_start = 0, ratio_end = 0;
  double voltage_start_V = 0, voltage_end_V = 0;
  double command_start = 0, command_end = 0;    // the mean motor command
  double setpoint_start = 0, setpoint_end = 0;  // the ground's hover thrust, m/s^2
  double voltage_last_V = 0;                    // the plant's at the end
  std::uint16_t firmware_mv_end = 0;            // what the firmware had filtered by then
  bool compensation_active = false;
};

DischargeHover hover_on_draining_battery(bool compensate) {
  hil::PlantConfig plant = shipped_plant();
  plant.battery.enabled = 1;
  plant.battery.capacity_Ah = 0.04;
  Ground ground(plant, kSeed, compensate);
  ground.arm();
  ground.take_off();
  const double mass_kg = double(firmware_for(plant, compensate).airframe.mass_kg);
  constexpr double kHeight_m = 1.0;
  constexpr double kFlight_s = 30.0, kWindow_s = 2.0, kSettle_s = 3.0;
  double integral_mps2 = 0.0;  // takes up what the thrust lacks, as the ground's thrust gain does
  const long n = std::lround(kFlight_s / ground.rig().period_s());
  double delivered[2] = {0, 0}, commanded[2] = {0, 0}, volts[2] = {0, 0}, command[2] = {0, 0},
         setpoint[2] = {0, 0};
  long samples[2] = {0, 0};
  for (long k = 0; k < n; ++k) {
    const hil::VehicleState& v = ground.truth();
    const Vec3 up_body = v.body.attitude.conjugate() * Vec3::UnitZ();
    const double e_m = kHeight_m - v.body.position_m.z();
    integral_mps2 += 2.0 * e_m * ground.rig().period_s();
    const double a = kG + integral_mps2 + 4.0 * e_m - 3.0 * v.body.velocity_mps.z();
    ground.thrust_mps2 = static_cast<float>(a / std::max(up_body.z(), 0.5));
    ground.rate_radps = {static_cast<float>(-3.0 * up_body.y()), static_cast<float>(3.0 * up_body.x()), 0.0f};
    ground.tick();
    const double t_s = static_cast<double>(k + 1) * ground.rig().period_s();
    if (std::getenv("PA_DEBUG_DISCHARGE") != nullptr && (k + 1) % 1000 == 0)
      std::printf("t %.1f z %.3f V %.3f soc %.3f a %.3f mode %d\n", t_s, ground.truth().body.position_m.z(),
                  ground.rig().plant().battery(pa::kVehicle1).voltage_V,
                  ground.rig().plant().battery(pa::kVehicle1).state_of_charge, a,
                  int(ground.vehicle().firmware().mode()));
    const int w = t_s >= kSettle_s && t_s < kSettle_s + kWindow_s ? 0 : t_s >= kFlight_s - kWindow_s ? 1 : -1;
    if (w < 0) continue;
    const hil::VehicleState& after = ground.truth();
    double thrust_N = 0, cmd = 0;
    for (int i = 0; i < 4; ++i) {
      thrust_N += after.motor_thrust_N[i];
      cmd += ground.vehicle().motor_commands().command[i] / 4.0;
    }
    delivered[w] += thrust_N;
    // What the firmware was asked: the setpoint the ground sent, on the airframe's mass.
    const double setpoint_mps2 = double(ground.vehicle().firmware().link().setpoint().thrust_mps2);
    commanded[w] += setpoint_mps2 * mass_kg;
    setpoint[w] += setpoint_mps2;
    volts[w] += ground.rig().plant().battery(pa::kVehicle1).voltage_V;
    command[w] += cmd;
    ++samples[w];
  }
  REQUIRE(ground.vehicle().firmware().mode() == Mode::flying);
  REQUIRE_FALSE(ground.rig().plant().vehicle_on_floor(pa::kVehicle1));
  DischargeHover r;
  r.ratio_start = delivered[0] / commanded[0];
  r.ratio_end = delivered[1] / commanded[1];
  r.voltage_start_V = volts[0] / double(samples[0]);
  r.voltage_end_V = volts[1] / double(samples[1]);
  r.command_start = command[0] / double(samples[0]);
  r.command_end = command[1] / double(samples[1]);
  r.setpoint_start = setpoint[0] / double(samples[0]);
  r.setpoint_end = setpoint[1] / double(samples[1]);
  r.voltage_last_V = ground.rig().plant().battery(pa::kVehicle1).voltage_V;
  r.firmware_mv_end = ground.vehicle().firmware().battery().filtered_mv();
  r.compensation_active = ground.vehicle().firmware().battery().active();
  return r;
}

}  // namespace

TEST_CASE("SIL: on a draining battery the compensation keeps the delivered thrust at the command") {
  const DischargeHover on = hover_on_draining_battery(true);
  const DischargeHover off = hover_on_draining_battery(false);
  for (const auto& [name, r] : {std::pair{"compensated", on}, std::pair{"uncompensated", off}})
    std::printf(
        "SIL discharge hover, %s: %.2f V -> %.2f V under load; delivered / commanded thrust %.4f -> %.4f; "
        "mean motor command %.4f -> %.4f; hover thrust setpoint %.3f -> %.3f m/s^2\n",
        name, r.voltage_start_V, r.voltage_end_V, r.ratio_start, r.ratio_end, r.command_start, r.command_end,
        r.setpoint_start, r.setpoint_end);
  // The pack sags well below full in both (the same plant and the same draw within a few %).
  CHECK(on.voltage_end_V < on.voltage_start_V - 0.8);
  CHECK(off.voltage_end_V < off.voltage_start_V - 0.8);
  // The firmware reads the plant's voltage (HIL_BATTERY, filtered over 0.1 s).
  CHECK(on.compensation_active);
  CHECK(double(on.firmware_mv_end) == Approx(on.voltage_last_V * 1000.0).margin(10.0));
  CHECK_FALSE(off.compensation_active);
  // Compensated, the thrust follows the command at every charge (the plant's per-motor gains
  // set the level, not the voltage); the motor commands rise with (V_ref / V)^2 to make it so.
  CHECK(on.ratio_end == Approx(on.ratio_start).epsilon(0.01));
  CHECK(on.command_end / on.command_start ==
        Approx(std::pow(on.voltage_start_V / on.voltage_end_V, 2.0)).epsilon(0.02));
  // Uncompensated, it falls with (V / V_ref)^2: the ground's loop pays with a larger command.
  CHECK(off.ratio_end / off.ratio_start ==
        Approx(std::pow(off.voltage_end_V / off.voltage_start_V, 2.0)).epsilon(0.02));
  CHECK(off.ratio_end < off.ratio_start * 0.9);
  // What the ground station sees: the hover thrust it must ask for stays where it was with the
  // compensation (its thrust gain k stays at its full-charge value) and climbs without.
  CHECK(on.setpoint_end == Approx(on.setpoint_start).epsilon(0.01));
  CHECK(off.setpoint_end > off.setpoint_start * 1.15);
}

TEST_CASE(
    "SIL: without the plant's battery the firmware reads the reference voltage and compensates nothing") {
  Ground ground;  // battery_enabled 0, as shipped
  REQUIRE(ground.rig().plant().config().battery.enabled == 0);
  ground.arm();
  CHECK(ground.vehicle().firmware().battery().active());
  CHECK(ground.vehicle().firmware().battery().filtered_mv() == 12600);
  CHECK(ground.vehicle().firmware().battery().factor() == 1.0f);
}

TEST_CASE("SIL: a body-rate step is tracked by the true vehicle as the rate loop predicts") {
  Ground ground;
  ground.arm();
  ground.take_off();

  const fw::VehicleConfig fwc =
      hil::sil::firmware_config_for(ground.rig().plant().config().vehicle, pa::kVehicle1);
  const std::vector<double> model =
      rate_step_model(double(fwc.rate.kp_per_s[1]), double(fwc.rate.ki_per_s2[1]),
                      double(fwc.airframe.motor_time_constant_s), 0.001, 0.3, 0.5);

  // Pitch at 1 rad/s for 0.3 s, then 0. Each frame goes out between the 200 Hz frames, so the
  // firmware reads it on the next tick: the end of that tick is the step's t = 0. The link guard
  // checks one ground frame at a time, so the step waits until it has checked the stream's; the
  // stop, 300 ticks later, meets the same phase of the 20-tick pattern of ground frames.
  while (ground.vehicle().firmware().guard().queued() > 0) ground.tick();
  ground.rate_radps = {0.0f, 1.0f, 0.0f};
  ground.send_setpoint();
  ground.tick();
  std::vector<double> pitch_rate, cross_rate;
  double nose_z = 0.0;
  for (std::size_t k = 0; k < model.size(); ++k) {
    if (k == 300) {
      // Positive pitch lowers the nose (fw/mixer.hpp): after 0.3 rad of it the body x-axis
      // points down by about sin(0.3).
      nose_z = (ground.truth().body.attitude * Vec3::UnitX()).z();
      ground.rate_radps = {0.0f, 0.0f, 0.0f};
      ground.send_setpoint();
    }
    ground.tick();
    const Vec3 w = ground.truth().body.rate_body_radps;
    pitch_rate.push_back(w.y());
    cross_rate.push_back(std::max(std::abs(w.x()), std::abs(w.z())));
  }
  const double t80 = time_to_reach(pitch_rate, 0.8), t80_model = time_to_reach(model, 0.8);
  const double peak = *std::max_element(pitch_rate.begin(), pitch_rate.begin() + 300);
  const double peak_model = *std::max_element(model.begin(), model.begin() + 300);
  double mean_late = 0.0, deviation = 0.0;
  for (std::size_t k = 200; k < 300; ++k) mean_late += pitch_rate[k] / 100.0;
  for (std::size_t k = 0; k < model.size(); ++k)
    deviation = std::max(deviation, std::abs(pitch_rate[k] - model[k]));
  const double cross_max = *std::max_element(cross_rate.begin(), cross_rate.end());

  std::printf(
      "SIL rate step: 80 %% after %.1f ms (model %.1f ms), peak %.3f (model %.3f), mean over 0.2-0.3 s %.4f "
      "rad/s, largest deviation from the model %.4f rad/s, roll/yaw at most %.4f rad/s, nose z %.3f "
      "(-sin 0.3 = %.3f), 0.2 s after the stop %.4f rad/s (model %.4f)\n",
      t80 * 1e3, t80_model * 1e3, peak, peak_model, mean_late, deviation, cross_max, nose_z, -std::sin(0.3),
      pitch_rate.back(), model.back());
  // The model is the firmware's own loop on an ideal body: kp 40/s through the 30 ms lag is a
  // second-order loop with wn = sqrt(kp / tau) = 36.5 rad/s and damping 1 / (2 sqrt(kp tau)) =
  // 0.46 (about 20 % overshoot), the slow integral (ki / kp = 1/s) adds a few per cent and leaves
  // a residual rate after the step that decays over a second. The true vehicle adds the IMU's
  // noise (3 mrad/s) and bias (5 mrad/s), the gyro's 1.1 mrad/s quantisation and the command's
  // 12-bit resolution; 5 ms in the rise time and 0.05 rad/s anywhere along the response bound
  // those with room, and fail for a wrong gain, inertia, lag or axis.
  REQUIRE(t80 > 0.0);
  CHECK(std::abs(t80 - t80_model) < 0.005);
  CHECK(std::abs(peak - peak_model) < 0.05);
  CHECK(std::abs(mean_late - 1.0) < 0.05);
  CHECK(deviation < 0.05);
  CHECK(cross_max < 0.05);
  CHECK(nose_z == Approx(-std::sin(0.3)).margin(0.03));
  CHECK(std::abs(pitch_rate.back()) < 0.1);
  CHECK(ground.vehicle().missed_ticks() == 0);
  CHECK(ground.undecodable() == 0);
}

TEST_CASE(
    "SIL: when the setpoint stream stops, the firmware hovers level, descends and lands with the motors off") {
  Ground ground;
  ground.arm();
  ground.take_off();
  ground.run(0.3);
  const double z_stop = ground.truth().body.position_m.z();
  const Vec3 accel_bias = ground.rig().plant().imu_model(pa::kVehicle1).accel_bias_mps2();
  const double learnt_bias = double(ground.vehicle().firmware().accel_bias_up_mps2());
  std::printf(
      "SIL failsafe: this seed's accelerometer bias (%.3f, %.3f, %.3f) m/s^2, learnt on the floor %.3f\n",
      accel_bias.x(), accel_bias.y(), accel_bias.z(), learnt_bias);
  // At rest for 0.3 s before the take-off: the mean of 300 samples, x and y biases second order.
  CHECK(learnt_bias == Approx(accel_bias.z()).margin(0.01));

  // The stream stops; the heartbeat goes on.
  ground.streaming = false;
  const double t_stop = ground.rig().t_s();
  double hover_tilt_max = 0.0, hover_vz_max = 0.0, descent_vz_sum = 0.0, landed_at = -1.0;
  double hover_s = -1.0, descent_s = -1.0, touchdown_vz = 0.0, touchdown_s = -1.0;
  int descent_n = 0;
  double descent_model_error_max = 0.0, vz_at_failsafe = 0.0, vz_estimate_at_failsafe = 0.0;
  bool was_on_floor = false;
  const fw::SupervisorConfig sup{};
  for (int k = 0; k < 8000 && landed_at < 0.0; ++k) {
    ground.tick();
    const Mode mode = ground.vehicle().firmware().mode();
    const double t = ground.rig().t_s() - t_stop;
    const hil::VehicleState& s = ground.truth();
    if (fw::action_for(mode) == fw::Action::level_hover) {  // the hold, then the failsafe hover
      if (hover_s < 0.0) {
        hover_s = t;
        vz_at_failsafe = s.body.velocity_mps.z();
        vz_estimate_at_failsafe = double(ground.vehicle().firmware().flight_vz_mps());
      }
      hover_tilt_max = std::max(hover_tilt_max, tilt_rad(s));
      hover_vz_max = std::max(hover_vz_max, std::abs(s.body.velocity_mps.z()));
    } else if (mode == Mode::failsafe_descent) {
      if (descent_s < 0.0) descent_s = t;
      // The descent speed, before the floor: the firmware's vertical loop (FailsafeController)
      // takes its speed from 0 to -descent_rate_mps, but the speed it holds is integrated from
      // its accelerometer, less the bias it learnt on the floor, from the speed it had
      // estimated in flight when the failsafe began; so the true speed is off by that
      // estimate's error and by what is left of the bias times the time.
      if (t > descent_s + 0.25 && touchdown_s < 0.0 &&
          !ground.rig().plant().vehicle_on_floor(pa::kVehicle1)) {
        const double rate = double(sup.descent_rate_mps);
        const double expected =
            -rate * (1.0 - std::exp(-double(fw::FailsafeController::kVerticalGain_per_s) * (t - descent_s))) +
            vz_at_failsafe - vz_estimate_at_failsafe - (accel_bias.z() - learnt_bias) * (t - hover_s);
        descent_vz_sum += s.body.velocity_mps.z();
        descent_model_error_max =
            std::max(descent_model_error_max, std::abs(s.body.velocity_mps.z() - expected));
        ++descent_n;
      }
    } else if (mode == Mode::landed || mode == Mode::killed) {
      landed_at = t;  // motors off (which of the two is checked below)
    }
    const bool on_floor = ground.rig().plant().vehicle_on_floor(pa::kVehicle1);
    if (on_floor && !was_on_floor && touchdown_s < 0.0) {
      touchdown_vz = s.body.velocity_mps.z();
      touchdown_s = t;
    }
    was_on_floor = on_floor;
  }
  ground.run(0.3);  // the motors spin down through their lag
  for (const auto& r : ground.modes())
    std::printf("  reported mode %d, reason %d at %.3f s\n", int(r.mode), int(r.reason), r.t_s - t_stop);
  const double descent_vz = descent_n > 0 ? descent_vz_sum / descent_n : 0.0;
  double thrust_N = 0.0;
  for (double f : ground.truth().motor_thrust_N) thrust_N += f;
  std::printf(
      "SIL failsafe: from %.2f m; hover after %.1f ms (max tilt %.2f deg, max |vz| %.3f m/s), descent after "
      "%.3f s at %.3f m/s (at most %.3f m/s off descent rate + bias drift), touchdown at %.3f m/s after %.3f s, motors off after %.3f s; thrust %.4f N at the end\n",
      z_stop, hover_s * 1e3, hover_tilt_max * 180.0 / M_PI, hover_vz_max, descent_s, descent_vz,
      descent_model_error_max, touchdown_vz, touchdown_s, landed_at, thrust_N);

  // Stale after setpoint_timeout_us (20 ms) plus the last frame's 5 ms period: within 25 ms.
  REQUIRE(hover_s > 0.0);
  CHECK(hover_s <= 0.026);
  // Level, and the vertical speed it estimated in flight brought to zero.
  CHECK(hover_tilt_max < 3.0 * M_PI / 180.0);
  CHECK(hover_vz_max < 0.15);
  REQUIRE(descent_s > 0.0);
  CHECK(descent_s - hover_s == Approx((sup.hold_max_us + sup.hover_before_descent_us) * 1e-6).margin(0.002));
  // It descends at descent_rate_mps, within what drag leaves (k/m 0.19/s against the 4/s loop:
  // about 0.02 m/s), the bias left after learning and noise.
  CHECK(descent_vz < -0.2);
  CHECK(descent_model_error_max < 0.05);
  REQUIRE(landed_at > 0.0);
  CHECK(ground.rig().plant().vehicle_on_floor(pa::kVehicle1));
  CHECK(tilt_rad(ground.truth()) < 0.05);
  for (double c : ground.vehicle().motor_commands().command) CHECK(c == 0.0);
  CHECK(thrust_N < 0.01);

  // What the ground saw in VEHICLE_HEARTBEAT: flying -> hold (levelled, no failsafe yet) ->
  // failsafe hover (setpoint stale) -> descent -> motors off on the floor.
  const auto& modes = ground.modes();
  REQUIRE(modes.size() == 7);
  CHECK(modes[0].mode == Mode::disarmed);
  CHECK(modes[1].mode == Mode::armed);
  CHECK(modes[2].mode == Mode::flying);
  CHECK(modes[3].mode == Mode::hold);
  CHECK(modes[3].reason == FailsafeReason::none);
  CHECK(modes[4].mode == Mode::failsafe_hover);
  CHECK(modes[4].reason == FailsafeReason::setpoint_stale);
  CHECK(modes[5].mode == Mode::failsafe_descent);
  // The descent ends in `landed`: touching down at the descent's speed, the feet's dampers give
  // a step of several g with a lateral part from the floor's friction; while landing, the impact
  // detector takes that for the floor (not a crash, whose peak threshold is lower), the firmware
  // restarts its integrated vertical speed from rest, its descent law asks for less thrust than
  // the floor now carries, and after ground_contact_us of that it turns the motors off.
  CHECK(modes[6].mode == Mode::landed);
  REQUIRE_FALSE(ground.impacts().empty());
  for (const auto& r : ground.impacts()) {
    std::printf("  IMPACT count %d, %s, class %d, peak %.1f m/s^2, onset %.4f s\n", int(r.impact.count),
                r.impact.final ? "final" : "provisional", int(r.impact.classification),
                double(r.impact.peak_mps2), static_cast<double>(r.impact.vehicle_time_us) * 1e-6 - t_stop);
    CHECK(r.impact.classification != ImpactClass::crash);
  }
  const double impact_s =
      static_cast<double>(ground.impacts().front().impact.vehicle_time_us) * 1e-6 - t_stop;
  CHECK(std::abs(impact_s - touchdown_s) < 0.01);
  CHECK(landed_at - touchdown_s == Approx(sup.ground_contact_us * 1e-6).margin(0.15));
  CHECK(ground.vehicle().missed_ticks() == 0);
  CHECK(ground.undecodable() == 0);
}

TEST_CASE(
    "SIL: from 4.9 m with a 3-sigma accelerometer bias the failsafe still descends at its rate and lands") {
  hil::PlantConfig plant = shipped_plant();
  plant.imu.accel_bias_sigma_mps2 = 0.3;  // 3 sigma of the shipped IMU
  // A seed whose draw puts a large bias on z (-0.41 m/s^2): with no bias estimate the integrated
  // speed drifts up by 0.4 m/s per s and the vehicle stalls and climbs.
  Ground ground(plant, 7);
  ground.arm();
  ground.take_off();
  // Up to where a throw leaves a vehicle: the firmware only sees its IMU, so moving the body is
  // a climb it did not notice (its speed is kept: the IMU would have felt it change).
  hil::Plant& p = ground.rig().plant();
  hil::VehicleState up = p.vehicle(pa::kVehicle1);
  up.body.position_m.z() = 4.9;
  p.set_vehicle(pa::kVehicle1, up);
  ground.run(0.2);
  const double bias_z = p.imu_model(pa::kVehicle1).accel_bias_mps2().z();
  const double learnt = double(ground.vehicle().firmware().accel_bias_up_mps2());

  ground.streaming = false;
  const double t_stop = ground.rig().t_s();
  const double z_stop = ground.truth().body.position_m.z();
  const fw::SupervisorConfig sup{};
  double z_max = z_stop, vz_sum = 0.0, touchdown_vz = 0.0;
  int vz_n = 0;
  bool landed = false;
  for (int k = 0; k < 20000 && !landed; ++k) {
    ground.tick();
    const hil::VehicleState& s = ground.truth();
    z_max = std::max(z_max, s.body.position_m.z());
    const Mode mode = ground.vehicle().firmware().mode();
    if (mode == Mode::failsafe_descent && s.body.position_m.z() < z_stop - 1.0 &&
        s.body.position_m.z() > 1.0) {
      vz_sum += s.body.velocity_mps.z();
      ++vz_n;
    }
    if (!p.vehicle_on_floor(pa::kVehicle1)) touchdown_vz = s.body.velocity_mps.z();
    landed = mode == Mode::landed;
  }
  const double vz_mean = vz_n > 0 ? vz_sum / vz_n : 0.0;
  std::printf(
      "SIL failsafe from %.2f m: accelerometer bias %.3f m/s^2 (learnt %.3f); highest %.2f m; descent %.3f m/s "
      "(commanded %.2f); touchdown %.3f m/s; landed after %.1f s\n",
      z_stop, bias_z, learnt, z_max, vz_mean, double(sup.descent_rate_mps), touchdown_vz,
      ground.rig().t_s() - t_stop);
  REQUIRE(std::abs(bias_z) > 0.3);  // the case this is about
  CHECK(learnt == Approx(bias_z).margin(0.03));
  // Never climbs, and descends near its rate: what is left of the bias after learning (x and y
  // biases tilt the measured up on the floor) drifts the integrated speed by 0.01-0.02 m/s per s.
  CHECK(z_max < z_stop + 0.1);
  CHECK(vz_mean == Approx(-double(sup.descent_rate_mps)).margin(0.2));
  CHECK(touchdown_vz > -0.8);
  CHECK(landed);
}
