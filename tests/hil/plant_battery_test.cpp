// Each vehicle's battery (hil/plant/battery.hpp): its voltage falls with the charge drawn and
// sags under load, a motor's thrust at a fixed command goes with the voltage squared, and with
// the battery off (the default) the plant steps exactly as before it existed.
#include <catch2/catch.hpp>

#include <cmath>

#include "hil/plant/battery.hpp"
#include "hil/plant/motor.hpp"
#include "hil/plant/plant.hpp"
#include "plant_test_configs.hpp"

using hil::MotorCommands;
using hil::Plant;
using hil::PlantConfig;
using hil::Vec3;

namespace {

MotorCommands all(double command) {
  MotorCommands m;
  m.command.fill(command);
  return m;
}

const MotorCommands kOff{};

PlantConfig with_battery(double charge_start) {
  PlantConfig c = plant_test::without_imu_errors();
  c.battery.enabled = 1;
  c.battery.charge_start = {charge_start, charge_start};
  return c;
}

}  // namespace

TEST_CASE("a 3S pack's open-circuit voltage: 12.6 V full, falling with the charge") {
  const hil::BatteryConfig b;
  CHECK(hil::battery_open_circuit_V(b, 1.0) == Approx(12.6));
  CHECK(hil::battery_open_circuit_V(b, 0.5) == Approx(11.52));
  CHECK(hil::battery_open_circuit_V(b, 0.0) == Approx(9.81));
  CHECK(hil::battery_open_circuit_V(b, 1.5) == hil::battery_open_circuit_V(b, 1.0));  // clamped
  double previous = hil::battery_open_circuit_V(b, 0.0);
  for (int k = 1; k <= 1000; ++k) {
    const double v = hil::battery_open_circuit_V(b, k / 1000.0);
    CHECK(v >= previous);
    previous = v;
  }
}

TEST_CASE("the terminal voltage sags by I R with I = P / V") {
  const double voc = 12.0, r = 0.04;
  CHECK(hil::battery_terminal_V(voc, 0.0, r) == voc);
  double previous = voc;
  for (const double p : {20.0, 50.0, 100.0, 200.0}) {
    const double v = hil::battery_terminal_V(voc, p, r);
    CHECK(v == Approx(voc - (p / v) * r).epsilon(1e-12));
    CHECK(v < previous);
    previous = v;
  }
  // Beyond the most the pack can give (V_oc^2 / 4 R = 900 W): half the open-circuit voltage.
  CHECK(hil::battery_terminal_V(voc, 2000.0, r) == Approx(6.0));
}

TEST_CASE("a motor's power goes with its thrust to the 1.5") {
  const hil::VehicleConfig v;
  // Hover of the 0.52 kg vehicle: 1.2753 N a motor, 1.2753^1.5 / (0.45 sqrt(2 1.225 pi 0.01)).
  CHECK(hil::motor_electrical_power_W(0.52 * 9.81 / 4.0, v, 1.225) == Approx(11.536).epsilon(1e-4));
  CHECK(hil::motor_electrical_power_W(0.0, v, 1.225) == 0.0);
  CHECK(hil::motor_electrical_power_W(4.0, v, 1.225) / hil::motor_electrical_power_W(1.0, v, 1.225) ==
        Approx(8.0));
}

TEST_CASE("a motor's thrust at a fixed command falls with the battery's voltage squared") {
  // Half charge: V_oc = 3 x 3.84 = 11.52 V. The motors stopped before the first step draw
  // nothing, so it sees V_oc: 0.5 x 3.2 N x (11.52 / 12.6)^2 = 1.33747 N (motors without lag).
  PlantConfig c = with_battery(0.5);
  c.vehicle.motor_time_constant_s = 0.0;
  Plant plant(c);
  plant.step(0.001, all(0.5), kOff);
  for (const double f : plant.vehicle(pa::kVehicle1).motor_thrust_N)
    CHECK(f == Approx(1.337469).epsilon(1e-6));
  CHECK(plant.battery(pa::kVehicle1).voltage_V == Approx(11.52));
  // The next step draws 4 x 1.33747^1.5 / 0.12484 = 49.558 W: V = (11.52 + sqrt(11.52^2 - 4 x
  // 49.558 x 0.04)) / 2 = 11.3453 V, 4.368 A, and the thrust is 1.6 N x (11.3453 / 12.6)^2.
  plant.step(0.001, all(0.5), kOff);
  for (const double f : plant.vehicle(pa::kVehicle1).motor_thrust_N)
    CHECK(f == Approx(1.297206).epsilon(1e-6));
  const hil::BatteryState& b = plant.battery(pa::kVehicle1);
  CHECK(b.voltage_V == Approx(11.345273).epsilon(1e-6));
  CHECK(b.current_A == Approx(4.368178).epsilon(1e-6));
  CHECK(b.charge_drawn_Ah == Approx(4.368178 * 0.001 / 3600.0).epsilon(1e-6));
  // The other vehicle's motors are off: no load, no sag.
  CHECK(plant.battery(pa::kVehicle2).voltage_V == Approx(11.52));
  CHECK(plant.battery(pa::kVehicle2).current_A == 0.0);
}

TEST_CASE("the battery sags under load and its voltage falls with the charge drawn") {
  PlantConfig c = with_battery(1.0);
  c.battery.capacity_Ah = 0.05;  // a small pack, so that 10 s of hover drain a fifth of it
  Plant plant(c);
  plant.set_vehicle(pa::kVehicle1, plant.hovering_vehicle(Vec3(0, 0, 20.0), 0.0));
  double last_voltage = 13.0, last_soc = 1.1;
  for (int s = 0; s < 10; ++s) {
    for (int k = 0; k < 1000; ++k) plant.step(0.001, plant.hover_commands(pa::kVehicle1), kOff);
    const hil::BatteryState& b = plant.battery(pa::kVehicle1);
    INFO("t " << s + 1 << " s");
    CHECK(b.voltage_V < last_voltage);
    CHECK(b.state_of_charge < last_soc);
    // Hover: about 46 W, 3.7 A at full charge, more as the voltage falls.
    CHECK(b.current_A > 3.6);
    CHECK(b.current_A < 4.2);
    CHECK(b.voltage_V < hil::battery_open_circuit_V(c.battery, b.state_of_charge) - 0.1);
    last_voltage = b.voltage_V;
    last_soc = b.state_of_charge;
  }
  const hil::BatteryState& b = plant.battery(pa::kVehicle1);
  // 10 s at about 3.8 A.
  CHECK(b.charge_drawn_Ah == Approx(10.0 * 3.8 / 3600.0).epsilon(0.05));
  CHECK(b.state_of_charge == Approx(1.0 - b.charge_drawn_Ah / 0.05).epsilon(1e-3));
  CHECK(b.voltage_V < 12.2);
  // The oracle's commands kept it hovering, near where it started.
  CHECK((plant.vehicle(pa::kVehicle1).body.position_m - Vec3(0, 0, 20.0)).norm() < 0.5);
  // Full command (2.7 N a motor at this voltage): about 12 A, 0.48 V of sag against 0.16 V.
  const double hover_V = b.voltage_V;
  for (int k = 0; k < 200; ++k) plant.step(0.001, all(1.0), kOff);
  const hil::BatteryState& full = plant.battery(pa::kVehicle1);
  CHECK(full.current_A > 11.5);
  CHECK(full.voltage_V < hover_V - 0.3);
  CHECK(full.voltage_V == Approx(hil::battery_open_circuit_V(c.battery, full.state_of_charge) -
                                 full.current_A * c.battery.internal_resistance_ohm));
}

TEST_CASE("a swapped pack is full, and drains from there") {
  PlantConfig c = with_battery(0.4);
  c.battery.capacity_Ah = 0.05;
  Plant plant(c);
  plant.set_vehicle(pa::kVehicle1, plant.hovering_vehicle(Vec3(0, 0, 20.0), 0.0));
  for (int k = 0; k < 1000; ++k) plant.step(0.001, plant.hover_commands(pa::kVehicle1), kOff);
  CHECK(plant.battery(pa::kVehicle1).state_of_charge < 0.4);
  plant.swap_battery(pa::kVehicle1);
  CHECK(plant.battery(pa::kVehicle1).state_of_charge == 1.0);
  CHECK(plant.battery(pa::kVehicle1).voltage_V == Approx(12.6));
  for (int k = 0; k < 1000; ++k) plant.step(0.001, plant.hover_commands(pa::kVehicle1), kOff);
  const hil::BatteryState& b = plant.battery(pa::kVehicle1);
  CHECK(b.state_of_charge < 1.0);
  CHECK(b.state_of_charge == Approx(1.0 - b.charge_drawn_Ah / 0.05).epsilon(1e-3));
  CHECK(b.voltage_V > 12.0);
  // The other vehicle's pack is untouched.
  CHECK(plant.battery(pa::kVehicle2).state_of_charge < 0.41);
}

TEST_CASE("with the battery off, a step makes the thrust of the law before the battery") {
  const PlantConfig c = plant_test::without_imu_errors();
  REQUIRE(c.battery.enabled == 0);
  Plant plant(c);
  hil::VehicleState hover = plant.hovering_vehicle(Vec3(0, 0, 5.0), 0.0);
  hover.motor_thrust_N = {1.0, 1.2, 0.7, 2.9};
  plant.set_vehicle(pa::kVehicle1, hover);
  MotorCommands cmd;
  cmd.command = {0.6, 0.1, 1.4, 0.35};
  plant.step(0.001, cmd, kOff);
  const double h_s = static_cast<double>(1000000) * 1e-9;  // the plant's step, as it computes it
  for (int i = 0; i < 4; ++i) {
    const double target = hil::motor_target_thrust_N(cmd.command[i], 1.0, c.vehicle.motor_thrust_max_N);
    CHECK(plant.vehicle(pa::kVehicle1).motor_thrust_N[i] ==
          hil::motor_thrust_after_N(hover.motor_thrust_N[i], target, c.vehicle.motor_time_constant_s, h_s));
  }
}

TEST_CASE("with the battery off, its keys and the envelope's change nothing, bit for bit") {
  const PlantConfig a = plant_test::without_imu_errors();
  PlantConfig b = a;
  b.battery.cells = 6;
  b.battery.capacity_Ah = 0.3;
  b.battery.internal_resistance_ohm = 0.5;
  b.battery.reference_voltage_V = 11.1;
  b.battery.charge_start = {0.2, 0.4};
  b.air_density_kgpm3 = 1.0;
  b.vehicle.rotor_radius_m = 0.05;
  b.vehicle.propulsion_efficiency = 0.2;
  b.envelope.thrust_scale_min = 0.5;
  b.envelope.motor_time_constant_max_s = 0.2;
  Plant plant_a(a, 7), plant_b(b, 7);
  for (Plant* p : {&plant_a, &plant_b}) {
    p->set_vehicle(pa::kVehicle1, p->hovering_vehicle(Vec3(0, 0, 1.0), 0.3));
    p->set_pole(Plant::make_pole(Vec3(0.2, 0, 2.0), Vec3(0.2, 0, 1), Vec3(0, 0, 1.0), Vec3(0, 1.0, 0)));
  }
  for (int k = 0; k < 1500; ++k) {
    MotorCommands m = plant_a.hover_commands(pa::kVehicle1);
    m.command[k % 4] += 0.05;
    plant_a.step(0.001, m, all(0.3));
    plant_b.step(0.001, m, all(0.3));
  }
  for (const pa::VehicleId v : {pa::kVehicle1, pa::kVehicle2}) {
    CHECK(plant_a.vehicle(v).body.position_m == plant_b.vehicle(v).body.position_m);
    CHECK(plant_a.vehicle(v).body.attitude.coeffs() == plant_b.vehicle(v).body.attitude.coeffs());
    CHECK(plant_a.vehicle(v).motor_thrust_N == plant_b.vehicle(v).motor_thrust_N);
    CHECK(plant_b.battery(v).charge_drawn_Ah == 0.0);
  }
  CHECK(plant_a.pole().body.position_m == plant_b.pole().body.position_m);
  CHECK(plant_a.pole().body.rate_body_radps == plant_b.pole().body.rate_body_radps);
}

TEST_CASE("a vehicle's scales act on it alone") {
  PlantConfig c = plant_test::without_imu_errors();
  c.vehicle.thrust_scale = {1.0, 0.9};
  c.vehicle.mass_scale = {1.0, 1.1};
  c.vehicle.inertia_scale = {1.0, 1.2};
  c.vehicle.motor_time_constant_scale = {1.0, 2.0};
  c.vehicle.motor_time_constant_s = 0.03;
  Plant plant(c);
  CHECK(plant.vehicle_mass_kg(pa::kVehicle1) == 0.52);
  CHECK(plant.vehicle_mass_kg(pa::kVehicle2) == Approx(0.572));
  CHECK(plant.vehicle_inertia_kgm2(pa::kVehicle2).z() == Approx(0.0054));
  // Vehicle 2's hover commands hold its weight with its thrust.
  CHECK(plant.hover_commands(pa::kVehicle2).command[0] == Approx(0.572 * 9.81 / 4.0 / (3.2 * 0.9)));
  // The lag: 30 ms against 60 ms, one vehicle's time constant after a step.
  plant.set_vehicle(pa::kVehicle1, plant.parked_vehicle(-1, 0, 0, pa::kVehicle1));
  plant.set_vehicle(pa::kVehicle2, plant.parked_vehicle(1, 0, 0, pa::kVehicle2));
  for (int k = 0; k < 30; ++k) plant.step(0.001, all(0.25), all(0.25));
  CHECK(plant.vehicle(pa::kVehicle1).motor_thrust_N[0] == Approx(0.8 * (1.0 - std::exp(-1.0))));
  CHECK(plant.vehicle(pa::kVehicle2).motor_thrust_N[0] == Approx(0.72 * (1.0 - std::exp(-0.5))));
  // A vehicle at hover thrust with its own weight stays put.
  plant.set_vehicle(pa::kVehicle2, plant.hovering_vehicle(Vec3(0, 0, 3.0), 0.0, pa::kVehicle2));
  for (int k = 0; k < 1000; ++k) plant.step(0.001, kOff, plant.hover_commands(pa::kVehicle2));
  CHECK((plant.vehicle(pa::kVehicle2).body.position_m - Vec3(0, 0, 3.0)).norm() < 1e-9);
}
