#include "groundstation/dds/telemetry_conversion.hpp"

#include <Eigen/Geometry>

#include "groundstation/dds/mocap_conversion.hpp"

namespace gs::dds {
namespace {

pa_arena_Vec3 vec3(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }
Eigen::Vector3d vec3(const pa_arena_Vec3& v) { return {v.x, v.y, v.z}; }

}  // namespace

Eigen::Quaterniond vehicle_attitude(const model::VehicleState& s) {
  // ^I_B R = Rz(psi) Ry(theta) Rx(phi) (estimation/mocap_pose.hpp).
  return Eigen::AngleAxisd(s.psi_rad, Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(s.theta_rad, Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(s.phi_rad, Eigen::Vector3d::UnitX());
}

pa_arena_Estimate vehicle_estimate_to_dds(const estimation::VehicleEstimate& estimate) {
  const model::VehicleState& s = estimate.state;
  const Eigen::Quaterniond q = vehicle_attitude(s);
  pa_arena_Estimate out{};
  out.position_m = vec3(s.p_m);
  out.velocity_mps = vec3(s.v_mps);
  out.attitude = {q.w(), q.x(), q.y(), q.z()};
  out.rate_radps = vec3(estimate.body_rates_radps);
  return out;
}

pa_arena_LinkState link_state_to_dds(const link::VehicleLinkStatus& status) {
  if (!status.heard) return pa_arena_link_unheard;
  return status.lost ? pa_arena_link_lost : pa_arena_link_up;
}

pa_arena_VehicleTelemetry vehicle_telemetry_to_dds(
    pa::VehicleId vehicle, double t_s, const link::VehicleLinkStatus& status, mission::Task task,
    const std::optional<estimation::VehicleEstimate>& estimate) {
  pa_arena_VehicleTelemetry out{};
  out.vehicle = vehicle.node();
  out.time_ns = to_nanoseconds(t_s);
  out.link = link_state_to_dds(status);
  out.mode = static_cast<std::uint8_t>(task);
  out.vehicle_mode = static_cast<std::uint8_t>(status.mode);
  out.estimate_valid = estimate.has_value();
  if (estimate) out.estimate = vehicle_estimate_to_dds(*estimate);
  return out;
}

pa_arena_PoleMode pole_mode_to_dds(estimation::PoleMode mode) {
  switch (mode) {
    case estimation::PoleMode::on_vehicle1: return pa_arena_pole_on_vehicle1;
    case estimation::PoleMode::on_vehicle2: return pa_arena_pole_on_vehicle2;
    case estimation::PoleMode::free: break;
  }
  return pa_arena_pole_free;
}

estimation::PoleMode pole_mode_from_dds(pa_arena_PoleMode mode) {
  switch (mode) {
    case pa_arena_pole_on_vehicle1: return estimation::PoleMode::on_vehicle1;
    case pa_arena_pole_on_vehicle2: return estimation::PoleMode::on_vehicle2;
    case pa_arena_pole_free: break;
  }
  return estimation::PoleMode::free;
}

pa_arena_PoleState pole_state_to_dds(const model::PoleState& state) {
  return {vec3(state.p_m), vec3(state.v_mps), vec3(state.n), vec3(state.omega_radps)};
}

model::PoleState pole_state_from_dds(const pa_arena_PoleState& state) {
  return {vec3(state.position_m), vec3(state.velocity_mps), vec3(state.direction), vec3(state.rate_radps)};
}

pa_arena_PoleTelemetry pole_telemetry_to_dds(const estimation::PoleEstimate& pole, double t_s,
                                             const std::optional<CatchForecast>& forecast) {
  pa_arena_PoleTelemetry out{};
  out.time_ns = to_nanoseconds(t_s);
  out.estimate_valid = pole.valid;
  out.mode = pole_mode_to_dds(pole.mode);
  out.estimate = pole_state_to_dds(pole.state);
  out.catch_predicted = forecast.has_value();
  if (forecast) {
    out.catch_time_ns = to_nanoseconds(forecast->t_s);
    out.catch_point_m = vec3(forecast->point_m);
    out.catch_vehicle = forecast->catcher.node();
  }
  return out;
}

}  // namespace gs::dds
