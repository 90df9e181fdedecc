#include "groundstation/model/pole_on_vehicle.hpp"

#include <cmath>

namespace gs::model {
namespace {

double pole_height_m(const PoleOnVehicleState& pole, const PoleParams& params) {
  const double length = params.half_length_m;
  return std::sqrt(length * length - pole.a_m * pole.a_m - pole.b_m * pole.b_m);  // c in (24)
}

}  // namespace

PoleOnVehicleState operator+(const PoleOnVehicleState& lhs, const PoleOnVehicleState& rhs) {
  return {lhs.a_m + rhs.a_m, lhs.b_m + rhs.b_m, lhs.a_dot_mps + rhs.a_dot_mps, lhs.b_dot_mps + rhs.b_dot_mps};
}

PoleOnVehicleState operator*(double scale, const PoleOnVehicleState& state) {
  return {scale * state.a_m, scale * state.b_m, scale * state.a_dot_mps, scale * state.b_dot_mps};
}

VehiclePoleState operator+(const VehiclePoleState& lhs, const VehiclePoleState& rhs) {
  return {lhs.vehicle + rhs.vehicle, lhs.pole + rhs.pole};
}

VehiclePoleState operator*(double scale, const VehiclePoleState& state) {
  return {scale * state.vehicle, scale * state.pole};
}

Eigen::Vector3d pole_direction_on_vehicle(const PoleOnVehicleState& pole, const PoleParams& params) {
  return Eigen::Vector3d(pole.a_m, pole.b_m, pole_height_m(pole, params)) / params.half_length_m;
}

Eigen::Vector3d pole_centre_velocity_relative_to_pivot_mps(const PoleOnVehicleState& pole,
                                                           const PoleParams& params) {
  const double c = pole_height_m(pole, params);
  return {pole.a_dot_mps, pole.b_dot_mps,
          -(pole.a_m * pole.a_dot_mps + pole.b_m * pole.b_dot_mps) / c};  // (26)
}

// r'' = -(3/4) f + mu r with mu = ((3/4) f . r - |r'|^2) / L^2: (28), (29), derived in the header.
Eigen::Vector2d pole_on_vehicle_acceleration_mps2(const PoleOnVehicleState& pole,
                                                  const Eigen::Vector3d& pivot_acceleration_mps2,
                                                  const PoleParams& params) {
  const double length = params.half_length_m;
  const Eigen::Vector3d r(pole.a_m, pole.b_m, pole_height_m(pole, params));
  const Eigen::Vector3d r_dot = pole_centre_velocity_relative_to_pivot_mps(pole, params);
  const Eigen::Vector3d specific_force =
      pivot_acceleration_mps2 + Eigen::Vector3d(0.0, 0.0, params.gravity_mps2);
  const double mu = (0.75 * specific_force.dot(r) - r_dot.squaredNorm()) / (length * length);
  const Eigen::Vector3d r_ddot = -0.75 * specific_force + mu * r;
  return {r_ddot.x(), r_ddot.y()};
}

PoleOnVehicleState pole_on_vehicle_derivative(const PoleOnVehicleState& pole,
                                              const Eigen::Vector3d& pivot_acceleration_mps2,
                                              const PoleParams& params) {
  const Eigen::Vector2d acc = pole_on_vehicle_acceleration_mps2(pole, pivot_acceleration_mps2, params);
  return {pole.a_dot_mps, pole.b_dot_mps, acc.x(), acc.y()};
}

VehiclePoleState vehicle_pole_dynamics(const VehiclePoleState& state, const VehicleInput& input,
                                       const PoleParams& params) {
  const VehicleState vehicle_rate = vehicle_dynamics(state.vehicle, input, params.gravity_mps2);
  return {vehicle_rate, pole_on_vehicle_derivative(state.pole, vehicle_rate.v_mps, params)};
}

double pole_on_vehicle_lagrangian_J(const PoleOnVehicleState& pole, const Eigen::Vector3d& pivot_p_m,
                                    const Eigen::Vector3d& pivot_v_mps, const PoleParams& params) {
  const Eigen::Vector3d n = pole_direction_on_vehicle(pole, params);
  const Eigen::Vector3d r_dot = pole_centre_velocity_relative_to_pivot_mps(pole, params);
  const Eigen::Vector3d p_p = pivot_p_m + params.half_length_m * n;     // (23)
  const Eigen::Vector3d v_p = pivot_v_mps + r_dot;                      // (26)
  const Eigen::Vector3d omega = n.cross(r_dot / params.half_length_m);  // (27)
  return 0.5 * params.mass_kg * v_p.squaredNorm() + 0.5 * pole_inertia_kgm2(params) * omega.squaredNorm() -
         params.mass_kg * params.gravity_mps2 * p_p.z();  // (25), g^T p_p with g = (0, 0, g)
}

double pole_on_vehicle_energy_J(const PoleOnVehicleState& pole, const Eigen::Vector3d& pivot_p_m,
                                const Eigen::Vector3d& pivot_v_mps, const PoleParams& params) {
  const Eigen::Vector3d n = pole_direction_on_vehicle(pole, params);
  const Eigen::Vector3d r_dot = pole_centre_velocity_relative_to_pivot_mps(pole, params);
  const Eigen::Vector3d omega = n.cross(r_dot / params.half_length_m);
  return 0.5 * params.mass_kg * (pivot_v_mps + r_dot).squaredNorm() +
         0.5 * pole_inertia_kgm2(params) * omega.squaredNorm() +
         params.mass_kg * params.gravity_mps2 * (pivot_p_m.z() + params.half_length_m * n.z());
}

PoleState free_flight_state_from_pole_on_vehicle(const PoleOnVehicleState& pole,
                                                 const Eigen::Vector3d& pivot_p_m,
                                                 const Eigen::Vector3d& pivot_v_mps,
                                                 const PoleParams& params) {
  const Eigen::Vector3d n = pole_direction_on_vehicle(pole, params);
  const Eigen::Vector3d r_dot = pole_centre_velocity_relative_to_pivot_mps(pole, params);
  PoleState out;
  out.p_m = pivot_p_m + params.half_length_m * n;
  out.v_mps = pivot_v_mps + r_dot;
  out.n = n;
  out.omega_radps = n.cross(r_dot / params.half_length_m);
  return out;
}

PoleOnVehicleState pole_on_vehicle_state_from_free_flight(const PoleState& pole, const PoleParams& params) {
  const Eigen::Vector3d r = params.half_length_m * pole.n;
  const Eigen::Vector3d r_dot = pole.omega_radps.cross(r);
  return {r.x(), r.y(), r_dot.x(), r_dot.y()};
}

}  // namespace gs::model
