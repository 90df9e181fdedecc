// The plant's vehicles: hover at hover thrust, motor lag and limits, per-motor mismatch, the
// sense of each motor's torque, and the floor.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "hil/plant/motor.hpp"
#include "hil/plant/plant.hpp"
#include "plant_test_configs.hpp"

using hil::MotorCommands;
using hil::Plant;
using hil::PlantConfig;
using hil::Vec3;

namespace {

PlantConfig quiet() { return plant_test::without_imu_errors(); }

MotorCommands all(double command) {
  MotorCommands m;
  m.command.fill(command);
  return m;
}

const MotorCommands kOff{};

}  // namespace

TEST_CASE("a vehicle with every motor at hover thrust and no mismatch hovers") {
  Plant plant(quiet());
  const Vec3 start(0.5, -0.3, 2.0);
  plant.set_vehicle(pa::kVehicle1, plant.hovering_vehicle(start, 0.7));
  const MotorCommands hover = plant.hover_commands(pa::kVehicle1);
  CHECK(hover.command[0] == Approx(0.52 * 9.81 / 4.0 / 3.2));
  for (int k = 0; k < 3000; ++k) plant.step(0.001, hover, kOff);
  const hil::RigidBodyState& b = plant.vehicle(pa::kVehicle1).body;
  CHECK((b.position_m - start).norm() < 1e-9);
  CHECK(b.velocity_mps.norm() < 1e-9);
  CHECK(b.rate_body_radps.norm() < 1e-12);
  CHECK(b.attitude.angularDistance(hil::Quat(Eigen::AngleAxisd(0.7, Vec3::UnitZ()))) < 1e-9);
  // The other vehicle stays parked where the plant put it.
  CHECK(plant.vehicle_on_floor(pa::kVehicle2));
}

TEST_CASE("each motor follows its command through a first-order lag, within its limits") {
  const PlantConfig c = quiet();
  const double tau = c.vehicle.motor_time_constant_s;
  Plant plant(c);
  plant.set_vehicle(pa::kVehicle1, plant.parked_vehicle(0, 0, 0));
  MotorCommands cmd;
  cmd.command = {0.25, 1.7, -0.4, std::nan("")};
  // One time constant after the step: 1 - 1/e of the way.
  for (int k = 0; k < 30; ++k) plant.step(0.001, cmd, kOff);
  const auto& f = plant.vehicle(pa::kVehicle1).motor_thrust_N;
  const double reached = 1.0 - std::exp(-0.030 / tau);
  CHECK(f[0] == Approx(0.25 * 3.2 * reached).epsilon(1e-12));
  CHECK(f[1] == Approx(3.2 * reached).epsilon(1e-12));  // command above 1: the maximum thrust
  CHECK(f[2] == 0.0);                                   // below 0: nothing
  CHECK(f[3] == 0.0);                                   // not a number: the ESC stops the motor
  double highest = 0.0;
  for (int k = 0; k < 2000; ++k) {
    plant.step(0.001, cmd, kOff);
    highest = std::max(highest, plant.vehicle(pa::kVehicle1).motor_thrust_N[1]);
  }
  CHECK(highest <= 3.2);
  CHECK(plant.vehicle(pa::kVehicle1).motor_thrust_N[1] == Approx(3.2).epsilon(1e-9));
  // Dropping the command: the thrust decays with the same lag.
  plant.step(0.030, kOff, kOff);
  CHECK(plant.vehicle(pa::kVehicle1).motor_thrust_N[1] == Approx(3.2 * std::exp(-0.030 / tau)).epsilon(1e-9));
}

TEST_CASE("a motor gain mismatch scales that motor's thrust and its limit") {
  PlantConfig c = quiet();
  c.vehicle.motor_gain[0] = {1.05, 0.95, 1.0, 1.0};
  Plant plant(c);
  plant.set_vehicle(pa::kVehicle1, plant.parked_vehicle(0, 0, 0));
  for (int k = 0; k < 1000; ++k) plant.step(0.001, all(1.0), kOff);
  const auto& f = plant.vehicle(pa::kVehicle1).motor_thrust_N;
  CHECK(f[0] == Approx(1.05 * 3.2).epsilon(1e-9));
  CHECK(f[1] == Approx(0.95 * 3.2).epsilon(1e-9));
  CHECK(f[2] == Approx(3.2).epsilon(1e-9));
}

TEST_CASE("a mismatched vehicle given nominal hover commands drifts off") {
  PlantConfig c = quiet();
  c.vehicle.motor_gain[0] = {1.05, 1.0, 1.0, 1.0};
  Plant plant(c);
  plant.set_vehicle(pa::kVehicle1, plant.hovering_vehicle(Vec3(0, 0, 3), 0.0));
  MotorCommands nominal = all(0.52 * 9.81 / 4.0 / 3.2);
  for (int k = 0; k < 500; ++k) plant.step(0.001, nominal, kOff);
  // Motor 0 (front right) is strong: it lifts the right side (negative roll) and the nose
  // (negative pitch), and the vehicle climbs.
  const Vec3 w = plant.vehicle(pa::kVehicle1).body.rate_body_radps;
  CHECK(w.x() < -0.1);
  CHECK(w.y() < -0.1);
  CHECK(plant.vehicle(pa::kVehicle1).body.position_m.z() > 3.0);
}

TEST_CASE("each motor turns the vehicle the way the firmware's mixer expects") {
  // fw/mixer.hpp: roll a(-f0 + f1 + f2 - f3), pitch a(-f0 + f1 - f2 + f3), yaw k(-f0 - f1 + f2 + f3).
  const int roll[4] = {-1, 1, 1, -1};
  const int pitch[4] = {-1, 1, -1, 1};
  const int yaw[4] = {-1, -1, 1, 1};
  const hil::VehicleConfig v;
  for (int i = 0; i < 4; ++i) {
    std::array<double, 4> f{};
    f[i] = 1.0;
    const hil::BodyWrench w = hil::rotor_wrench(v, f);
    const double a = v.arm_length_m / std::sqrt(2.0);
    INFO("motor " << i);
    CHECK(w.force_N.isApprox(Vec3(0, 0, 1.0)));
    CHECK(w.torque_Nm.x() == Approx(roll[i] * a));
    CHECK(w.torque_Nm.y() == Approx(pitch[i] * a));
    CHECK(w.torque_Nm.z() == Approx(yaw[i] * v.yaw_moment_per_thrust_m));
  }
}

TEST_CASE("a vehicle climbs with the acceleration its thrust gives") {
  PlantConfig c = quiet();
  c.vehicle.drag_Nspm = 0.0;
  Plant plant(c);
  hil::VehicleState s = plant.hovering_vehicle(Vec3(0, 0, 1), 0.0);
  s.motor_thrust_N.fill(1.2 * 0.52 * 9.81 / 4.0);  // already at the commanded thrust
  plant.set_vehicle(pa::kVehicle1, s);
  const MotorCommands climb = all(1.2 * 0.52 * 9.81 / 4.0 / 3.2);
  for (int k = 0; k < 1000; ++k) plant.step(0.001, climb, kOff);
  CHECK(plant.vehicle(pa::kVehicle1).body.position_m.z() == Approx(1.0 + 0.5 * 0.2 * 9.81).epsilon(1e-9));
  // A perfect IMU reads the thrust over the mass.
  CHECK(plant.true_specific_force_mps2(pa::kVehicle1).z() == Approx(1.2 * 9.81).epsilon(1e-9));
}

TEST_CASE("the floor stops a falling vehicle, which comes to rest on its feet") {
  const PlantConfig c = quiet();
  Plant plant(c);
  plant.set_vehicle(pa::kVehicle1, plant.hovering_vehicle(Vec3(0, 0, 1.0), 0.3));
  double lowest = 1.0;
  for (int k = 0; k < 3000; ++k) {
    plant.step(0.001, kOff, kOff);
    lowest = std::min(lowest, plant.vehicle(pa::kVehicle1).body.position_m.z());
  }
  const hil::RigidBodyState& b = plant.vehicle(pa::kVehicle1).body;
  CHECK(plant.vehicle_on_floor(pa::kVehicle1));
  // Resting: the feet carry the weight, each sunk by m g / (4 k).
  const double sink = c.vehicle.mass_kg * c.gravity_mps2 / (4.0 * c.contact.floor_stiffness_Npm);
  CHECK(b.position_m.z() == Approx(c.vehicle.foot_depth_m - sink).margin(1e-6));
  CHECK(b.velocity_mps.norm() < 1e-6);
  // Falling from 1 m onto a stiff floor never sinks more than a few centimetres.
  CHECK(lowest > c.vehicle.foot_depth_m - 0.03);
  CHECK((b.attitude * Vec3::UnitZ()).z() > 1.0 - 1e-9);
  CHECK(std::abs(b.position_m.x()) < 1e-6);
  // Standing on the floor, a perfect IMU reads +g.
  CHECK(plant.true_specific_force_mps2(pa::kVehicle1).z() == Approx(9.81).epsilon(1e-6));
}

// The plant skips a vehicle's feet while its centre is higher than they reach (plant.hpp,
// Kinematics::feet_clear): whatever the attitude, the lowest foot must still meet the floor.
TEST_CASE("a vehicle falling tilted meets the floor with its lowest foot, whatever its attitude") {
  const PlantConfig c = quiet();
  for (const double roll_rad : {0.0, 0.4, 0.9, 1.4}) {
    Plant plant(c);
    hil::VehicleState v = plant.hovering_vehicle(Vec3(0, 0, 0.4), 0.0);
    v.body.attitude = hil::Quat(Eigen::AngleAxisd(roll_rad, Vec3(1.0, 1.0, 0.0).normalized()));
    v.motor_thrust_N.fill(0.0);
    plant.set_vehicle(pa::kVehicle1, v);
    auto lowest_foot_m = [&plant, &c] {
      const hil::RigidBodyState& b = plant.vehicle(pa::kVehicle1).body;
      double lowest = 1e9;
      for (int f = 0; f < 4; ++f) {
        const Vec3 foot = hil::motor_position_body_m(c.vehicle, f) - Vec3(0, 0, c.vehicle.foot_depth_m);
        lowest = std::min(lowest, (b.position_m + b.attitude * foot).z());
      }
      return lowest;
    };
    double before_m = lowest_foot_m();
    int k = 0;
    for (; k < 2000 && !plant.vehicle_on_floor(pa::kVehicle1); ++k) {
      before_m = lowest_foot_m();
      plant.step(0.001, kOff, kOff);
    }
    INFO("roll " << roll_rad << " rad: touched after " << k << " ms, lowest foot " << before_m
                 << " m before, " << lowest_foot_m() << " m after");
    REQUIRE(plant.vehicle_on_floor(pa::kVehicle1));
    // Touched in the step in which the lowest foot went below the floor (falling ~3 m/s).
    CHECK(before_m >= 0.0);
    CHECK(lowest_foot_m() < 0.0);
    CHECK(lowest_foot_m() > -0.005);
  }
}

TEST_CASE("the plant refuses a non-finite state and keeps the one it had") {
  Plant plant(quiet());
  plant.set_vehicle(pa::kVehicle1, plant.hovering_vehicle(Vec3(0, 0, 1), 0.0));
  hil::VehicleState bad = plant.hovering_vehicle(Vec3(0, 0, 1), 0.0);
  bad.body.velocity_mps.x() = std::nan("");
  CHECK_THROWS_AS(plant.set_vehicle(pa::kVehicle1, bad), std::invalid_argument);
  hil::PoleState pole = plant.pole();
  pole.body.attitude.coeffs().setZero();
  CHECK_THROWS_AS(plant.set_pole(pole), std::invalid_argument);
  CHECK(plant.vehicle(pa::kVehicle1).body.velocity_mps.allFinite());
  // Stepping by a non-finite or negative interval does nothing.
  plant.step(std::nan(""), kOff, kOff);
  plant.step(-1.0, kOff, kOff);
  CHECK(plant.t_s() == 0.0);
}
