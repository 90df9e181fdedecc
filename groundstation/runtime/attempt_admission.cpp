#include "groundstation/runtime/attempt_admission.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace gs::runtime {

std::string_view refusal_name(AttemptRefusal refusal) {
  switch (refusal) {
    case AttemptRefusal::none: return "none";
    case AttemptRefusal::busy: return "ground_station_busy";
    case AttemptRefusal::not_of_act: return "not_of_act";
    case AttemptRefusal::target_not_planned: return "target_throw_not_planned";
    case AttemptRefusal::too_weak: return "vehicle_too_weak";
    case AttemptRefusal::outside_volume: return "outside_arena_volume";
  }
  return "?";
}

Admission admit_request(bool attempt_running, pa::VehicleId thrower) {
  if (attempt_running) return {AttemptRefusal::busy, "an attempt is running"};
  if (!pa::is_act_vehicle(thrower))
    return {AttemptRefusal::not_of_act, "vehicle " + std::to_string(thrower.node()) + " is not of the act"};
  return {};
}

double peak_thrust_mps2(const planning::ThrowTrajectory& trajectory, double pole_to_vehicle_mass) {
  double peak_mps2 = 0.0;
  for (std::size_t i = 0; i < trajectory.input.size(); ++i) {
    const model::PlanarInput<double>& u = trajectory.input[i];
    const model::PlanarState<double> s =
        i < trajectory.state.size() ? trajectory.state[i] : model::PlanarState<double>::Zero();
    const double push_mps2 = model::planar_normal_force_per_mass_mps2(s, u, trajectory.params);
    peak_mps2 = std::max(peak_mps2, u(model::planar::kThrust) + pole_to_vehicle_mass * push_mps2);
  }
  return peak_mps2;
}

double thrust_ceiling_mps2(const VehicleThrust& vehicle, const ThrustAdmission& settings) {
  const double volts = vehicle.battery_V;
  // No voltage reported (0: none, or no compensation on board): the ceiling is k's alone.
  const double sag =
      volts > 0.0 ? std::min(1.0, std::pow(volts / settings.battery_reference_voltage_V, 2.0)) : 1.0;
  return vehicle.gain * sag * settings.full_thrust_mps2;
}

bool pack_spent(const VehicleThrust& vehicle, double needed_mps2, const PackSwap& swap,
                const ThrustAdmission& settings) {
  if (!(vehicle.battery_V > 0.0)) return false;
  const double wanted_mps2 = swap.margin * needed_mps2;
  const double fresh_mps2 = thrust_ceiling_mps2({vehicle.vehicle, vehicle.gain, 0.0}, settings);  // no sag
  const double floor_mps2 = fresh_mps2 >= wanted_mps2 ? wanted_mps2 : swap.weak_sag * fresh_mps2;
  return thrust_ceiling_mps2(vehicle, settings) < floor_mps2;
}

pa::VehicleId stronger_thrower(const VehicleThrust& first, const VehicleThrust& second,
                               const ThrustAdmission& settings) {
  return thrust_ceiling_mps2(second, settings) > thrust_ceiling_mps2(first, settings) ? second.vehicle
                                                                                      : first.vehicle;
}

std::string thrust_shortfall(const VehicleThrust& vehicle, double needed_mps2, const char* part,
                             const ThrustAdmission& settings) {
  const double k = vehicle.gain;
  const double volts = vehicle.battery_V;
  const double most_mps2 = thrust_ceiling_mps2(vehicle, settings);
  if (most_mps2 >= settings.min_thrust_fraction * needed_mps2) return {};
  char at[32] = "";
  if (volts > 0.0) std::snprintf(at, sizeof at, " at %.2f V", volts);
  char text[240];
  std::snprintf(
      text, sizeof text,
      "vehicle %u is too weak to %s: thrust gain %.2f%s gives %.1f m/s^2 at most, the %s needs %.1f",
      static_cast<unsigned>(vehicle.vehicle.node()), part, k, at, most_mps2, part,
      settings.min_thrust_fraction * needed_mps2);
  return text;
}

Admission admit_vehicles(const planning::ThrowTrajectory* flown, const VehicleThrust& thrower,
                         const std::optional<VehicleThrust>& catcher, const ThrustAdmission& settings) {
  if (flown == nullptr)
    return {AttemptRefusal::target_not_planned, "the throw to the target cannot be planned"};
  if (std::string why = thrust_shortfall(thrower, peak_thrust_mps2(*flown, settings.pole_to_vehicle_mass),
                                         "throw", settings);
      !why.empty())
    return {AttemptRefusal::too_weak, why};
  if (catcher) {
    if (std::string why = thrust_shortfall(*catcher, settings.catch_peak_mps2, "catch", settings);
        !why.empty())
      return {AttemptRefusal::too_weak, why};
  }
  return {};
}

namespace {

// Empty if `lo`..`hi` (arena coordinates) lies inside the volume by its margin, else which wall
// and by how much.
std::string breach(const char* what, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                   const ArenaVolume& volume) {
  static constexpr const char* kAxes = "xyz";
  for (int i = 0; i < 3; ++i) {
    const double below = volume.min_m(i) + volume.margin_m - lo(i);
    const double above = hi(i) - (volume.max_m(i) - volume.margin_m);
    if (below <= 0.0 && above <= 0.0) continue;
    char text[200];
    std::snprintf(text, sizeof text,
                  "%s reaches %c = %.2f m, %.2f m beyond the arena's %s %.2f m (margin %.2f m)", what,
                  kAxes[i], below > 0.0 ? lo(i) : hi(i), below > 0.0 ? below : above,
                  below > 0.0 ? "lower bound" : "upper bound",
                  below > 0.0 ? volume.min_m(i) : volume.max_m(i), volume.margin_m);
    return text;
  }
  return {};
}

}  // namespace

bool outside_volume(const Eigen::Vector3d& p_m, const ArenaVolume& volume) {
  return (p_m.array() < volume.min_m.array()).any() || (p_m.array() > volume.max_m.array()).any();
}

Admission admit_volume(const planning::ThrowReach& reach, const control::ThrowFrame& frame,
                       const Eigen::Vector3d& catch_point_m, const ArenaVolume& volume) {
  // The frame's box turned into the arena: the bounds of its eight corners.
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d c((corner & 1) ? reach.max_m.x() : reach.min_m.x(),
                            (corner & 2) ? reach.max_m.y() : reach.min_m.y(),
                            (corner & 4) ? reach.max_m.z() : reach.min_m.z());
    const Eigen::Vector3d a = frame.to_arena(c);
    lo = lo.cwiseMin(a);
    hi = hi.cwiseMax(a);
  }
  if (std::string why = breach("the throw", lo, hi, volume); !why.empty())
    return {AttemptRefusal::outside_volume, why};
  if (std::string why = breach("the catch", catch_point_m, catch_point_m, volume); !why.empty())
    return {AttemptRefusal::outside_volume, why};
  return {};
}

}  // namespace gs::runtime
