#include "hil/plant/battery.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace hil {

namespace {
// A LiPo cell's resting voltage at 0 %, 5 %, ..., 100 % charge: the curve published in hobby
// LiPo charts (a flat middle near 3.8 V, a knee below 10 %, a rise above 80 %).
constexpr std::array<double, 21> kCellVoltage_V = {3.27, 3.61, 3.69, 3.71, 3.73, 3.75, 3.77,
                                                   3.79, 3.80, 3.82, 3.84, 3.85, 3.87, 3.91,
                                                   3.95, 3.98, 4.02, 4.08, 4.11, 4.15, 4.20};
}  // namespace

double lipo_cell_open_circuit_V(double state_of_charge) {
  const double x = std::clamp(state_of_charge, 0.0, 1.0) * 20.0;
  const std::size_t i = std::min<std::size_t>(static_cast<std::size_t>(x), 19);
  const double f = x - static_cast<double>(i);
  return kCellVoltage_V[i] + f * (kCellVoltage_V[i + 1] - kCellVoltage_V[i]);
}

double battery_open_circuit_V(const BatteryConfig& battery, double state_of_charge) {
  return battery.cells * lipo_cell_open_circuit_V(state_of_charge);
}

double battery_terminal_V(double open_circuit_V, double power_W, double resistance_ohm) {
  // V = V_oc - R P / V, i.e. V^2 - V_oc V + P R = 0.
  const double discriminant = open_circuit_V * open_circuit_V - 4.0 * power_W * resistance_ohm;
  return 0.5 * (open_circuit_V + std::sqrt(std::max(0.0, discriminant)));
}

double motor_electrical_power_W(double thrust_N, const VehicleConfig& vehicle, double air_density_kgpm3) {
  const double t = std::max(0.0, thrust_N);
  const double disc_m2 = std::numbers::pi * vehicle.rotor_radius_m * vehicle.rotor_radius_m;
  return t * std::sqrt(t) / (vehicle.propulsion_efficiency * std::sqrt(2.0 * air_density_kgpm3 * disc_m2));
}

double thrust_voltage_factor(double voltage_V, double reference_voltage_V) {
  const double r = voltage_V / reference_voltage_V;
  return r * r;
}

}  // namespace hil
