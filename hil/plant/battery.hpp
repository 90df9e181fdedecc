// Each vehicle's battery and what it does to the motors (PlantConfig::battery, off by default).
//
//  - Open-circuit voltage over the state of charge: a LiPo cell's resting curve, 4.20 V full,
//    3.27 V empty, 3.84 V at half; 3 cells in series give 12.6 V full and the 11.1 V rating
//    (3.7 V a cell, the mean under a standard discharge; at rest the curve stays above it down to
//    about 10 % charge).
//  - Sag: the terminals give V = V_oc(soc) - I R, with the current I = P / V the motors' power
//    draws: V = (V_oc + sqrt(V_oc^2 - 4 P R)) / 2, the root that tends to V_oc at no load.
//  - Power: momentum theory with a figure of merit, P = T^1.5 / (eta sqrt(2 rho A)) per motor.
//    Static thrust tables of small brushless motors and propellers show what it says: the thrust
//    per watt falls as the thrust rises (about T^-0.5), so a full-throttle climb costs far more
//    than its share of the hover's current. With the default rotor (0.1 m, eta 0.45) a hover of
//    the 0.52 kg vehicle draws about 46 W (4 A at 11.4 V, 11 g/W), all four at full command 183 W (7 g/W),
//    the range such tables give for 8-inch propellers.
//  - Thrust: the command is a thrust fraction at the reference voltage (HIL_MOTORS, types.hpp),
//    so the ESC's duty goes with its square root; a brushless motor turns at a speed roughly
//    proportional to the voltage applied, duty x V, and a propeller's thrust goes with the speed
//    squared: T = command x gain x T_max x (V / V_ref)^2.
#pragma once

#include "hil/plant/plant_config.hpp"

namespace hil {

struct BatteryState {
  double charge_drawn_Ah = 0.0;  // since the start
  double state_of_charge = 1.0;  // 0 empty .. 1 full
  double voltage_V = 0.0;        // at the terminals, under the load of the last step
  double current_A = 0.0;
};

// A LiPo cell at rest at `state_of_charge` (clamped to 0 .. 1), linear between 5 % points.
double lipo_cell_open_circuit_V(double state_of_charge);
double battery_open_circuit_V(const BatteryConfig& battery, double state_of_charge);

// The terminal voltage of a pack with open-circuit voltage `open_circuit_V` and internal
// resistance `resistance_ohm` delivering `power_W`; beyond the most it can deliver
// (V_oc^2 / 4 R), half the open-circuit voltage.
double battery_terminal_V(double open_circuit_V, double power_W, double resistance_ohm);

// The electrical power a motor draws to make `thrust_N`.
double motor_electrical_power_W(double thrust_N, const VehicleConfig& vehicle, double air_density_kgpm3);

// The factor on a motor's thrust at terminal voltage `voltage_V`: (V / V_ref)^2.
double thrust_voltage_factor(double voltage_V, double reference_voltage_V);

}  // namespace hil
