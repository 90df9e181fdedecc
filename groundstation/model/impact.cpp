#include "groundstation/model/impact.hpp"

#include <Eigen/Geometry>
#include <cmath>

namespace gs::model {

PoleState with_lower_end_as_base(const PoleState& state) {
  PoleState out = state;
  if (state.n.z() < 0.0) out.n = -state.n;
  return out;
}

Eigen::Vector3d pole_angular_momentum_about(const PoleState& state, const Eigen::Vector3d& point_m,
                                            const PoleParams& params) {
  const Eigen::Vector3d omega_normal = state.omega_radps - state.omega_radps.dot(state.n) * state.n;
  return pole_inertia_kgm2(params) * omega_normal + params.mass_kg * (state.p_m - point_m).cross(state.v_mps);
}

ImpactResult impact_map(const PoleState& before, const Eigen::Vector3d& plate_velocity_mps,
                        const PoleParams& params) {
  const double length = params.half_length_m;
  const PoleState pole = normalised_pole_state(with_lower_end_as_base(before));
  ImpactResult result;
  result.contact_point_m = pole.p_m - length * pole.n;
  result.after = pole;
  result.after.omega_radps =
      0.25 * pole.omega_radps + (0.75 / length) * pole.n.cross(pole.v_mps - plate_velocity_mps);
  result.after.v_mps = plate_velocity_mps + length * result.after.omega_radps.cross(pole.n);
  result.on_vehicle = pole_on_vehicle_state_from_free_flight(result.after, params);
  result.impulse_Ns = params.mass_kg * (result.after.v_mps - pole.v_mps);
  return result;
}

PlanarPoleKinematics planar_kinematics(const PoleState& state) {
  return {std::atan2(state.n.x(), state.n.z()), state.omega_radps.y(), state.v_mps.x(), state.v_mps.z()};
}

PlanarPoleKinematics planar_kinematics_from_lower_end(const PoleState& state) {
  return planar_kinematics(with_lower_end_as_base(state));
}

double post_impact_rate_radps(const PlanarPoleKinematics& before, const PoleParams& params) {
  const double c = std::cos(before.alpha_rad);
  const double s = std::sin(before.alpha_rad);
  return 0.25 * before.alpha_dot_radps +
         (0.75 / params.half_length_m) * (before.x_dot_mps * c - before.z_dot_mps * s);  // (40)
}

double upright_energy_J(const PoleParams& params) {
  return params.mass_kg * params.gravity_mps2 * params.half_length_m;
}

double pivoted_pole_energy_J(double alpha_rad, double alpha_dot_radps, const PoleParams& params) {
  const double length = params.half_length_m;
  const double tip_speed = length * alpha_dot_radps;
  return params.mass_kg * params.gravity_mps2 * length * std::cos(alpha_rad) +
         0.5 * params.mass_kg * tip_speed * tip_speed +
         0.5 * pole_inertia_kgm2(params) * alpha_dot_radps * alpha_dot_radps;  // (41)
}

double swing_up_rate_radps(double alpha_rad, const PoleParams& params) {
  return -std::sqrt(3.0 * params.gravity_mps2 / params.half_length_m) * std::sin(0.5 * alpha_rad);
}

double catching_condition_residual_radps(const PlanarPoleKinematics& before, const PoleParams& params) {
  return 4.0 * (post_impact_rate_radps(before, params) - swing_up_rate_radps(before.alpha_rad, params));
}

double catching_condition_residual_radps(const PoleState& before, const PoleParams& params) {
  return catching_condition_residual_radps(planar_kinematics_from_lower_end(before), params);
}

double flight_plane_yaw_rad(const PoleState& state) {
  constexpr double kTurning_radps = 1e-3, kMoving_mps = 1e-3;
  const Eigen::Vector2d axis = state.omega_radps.head<2>();
  if (axis.norm() > kTurning_radps)
    return std::atan2(-axis.x(), axis.y());  // +y turned by the yaw is the axis
  const Eigen::Vector2d velocity = state.v_mps.head<2>();
  if (velocity.norm() > kMoving_mps) return std::atan2(velocity.y(), velocity.x());
  return 0.0;
}

PoleState turned_by_yaw(const PoleState& state, double yaw_rad) {
  const Eigen::Matrix3d to_plane = Eigen::AngleAxisd(-yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return {to_plane * state.p_m, to_plane * state.v_mps, to_plane * state.n, to_plane * state.omega_radps};
}

}  // namespace gs::model
