#include "groundstation/adaptation/throw_evaluation.hpp"

#include "groundstation/model/impact.hpp"

namespace gs::adaptation {
namespace {

bool head_is_lower(const model::PoleState& state) { return state.n.z() < 0.0; }

// The end taken as the contact end: the tail p - L n, or the head if `head`.
Eigen::Vector3d end_point(const model::PoleState& state, bool head, const model::PoleParams& params) {
  return head ? model::pole_head_end_m(state, params) : model::pole_tail_end_m(state, params);
}

// Eq. (42) (model/impact.hpp's form) in the flight's plane with a fixed contact end: continuous in
// time for that end.
double residual_with_end(const model::PoleState& state, bool head, double plane_yaw_rad,
                         const model::PoleParams& params) {
  model::PoleState based = model::turned_by_yaw(state, plane_yaw_rad);
  if (head) based.n = -based.n;
  return model::catching_condition_residual_radps(model::planar_kinematics(based), params);
}

bool increasing(std::span<const TimedPoleState> flight) {
  for (std::size_t i = 1; i < flight.size(); ++i) {
    if (!(flight[i].t_s > flight[i - 1].t_s)) return false;
  }
  return true;
}

}  // namespace

std::optional<OptimalCatchEvaluation> evaluate_optimal_catch(
    std::span<const TimedPoleState> flight, double launch_t_s, const model::PoleParams& params,
    const planning::CatchingInstantOptions& continuation) {
  if (flight.empty() || !increasing(flight)) return std::nullopt;
  const double yaw = model::flight_plane_yaw_rad(flight.front().state);
  for (std::size_t i = 0; i + 1 < flight.size(); ++i) {
    const TimedPoleState& a = flight[i];
    const TimedPoleState& b = flight[i + 1];
    const bool head = head_is_lower(a.state);
    // Across the pole's passing the horizontal the contact end changes and (42) jumps; a catch of
    // a horizontal pole is not a root of it (planning/catching_instant.hpp skips it likewise).
    if (head_is_lower(b.state) != head) continue;
    const double r_a = residual_with_end(a.state, head, yaw, params);
    const double r_b = residual_with_end(b.state, head, yaw, params);
    const bool root_at_a = (i == 0 && r_a == 0.0);
    if (!root_at_a && !((r_a > 0.0 && r_b <= 0.0) || (r_a < 0.0 && r_b >= 0.0))) continue;
    const double fraction = root_at_a ? 0.0 : r_a / (r_a - r_b);
    const Eigen::Vector3d end_a = end_point(a.state, head, params);
    const Eigen::Vector3d end_b = end_point(b.state, head, params);
    const Eigen::Vector3d end = end_a + fraction * (end_b - end_a);
    OptimalCatchEvaluation result;
    result.point.t_s = a.t_s + fraction * (b.t_s - a.t_s) - launch_t_s;
    result.point.height_m = end.z();
    result.point.xy_m = end.head<2>();
    return result;
  }
  // Not met while observed: continue the last observed state with the free-flight model.
  const TimedPoleState& last = flight.back();
  planning::CatchingInstantOptions same_plane = continuation;
  same_plane.plane_yaw_rad = yaw;
  const planning::CatchingInstant instant = planning::find_catching_instant(last.state, params, same_plane);
  if (!instant.found) return std::nullopt;
  OptimalCatchEvaluation result;
  result.point.t_s = last.t_s + instant.t_s - launch_t_s;
  result.point.height_m = instant.catch_height_m;
  result.point.xy_m = instant.catch_point_m;
  result.extrapolated = true;
  return result;
}

std::optional<CatchPoint> lower_end_crossing(std::span<const TimedPoleState> flight, double height_m,
                                             double launch_t_s, const model::PoleParams& params) {
  if (!increasing(flight)) return std::nullopt;
  for (std::size_t i = 0; i + 1 < flight.size(); ++i) {
    const TimedPoleState& a = flight[i];
    const TimedPoleState& b = flight[i + 1];
    if (!(model::pole_lower_end_m(a.state, params).z() > height_m)) continue;
    // Follow the end that is the lower one at b through the step, so the interpolation stays on
    // one end even if the pole passes the horizontal in between.
    const bool head = head_is_lower(b.state);
    const Eigen::Vector3d end_a = end_point(a.state, head, params);
    const Eigen::Vector3d end_b = end_point(b.state, head, params);
    if (end_b.z() > height_m) continue;
    const double fraction = (end_a.z() - height_m) / (end_a.z() - end_b.z());
    CatchPoint point;
    point.t_s = a.t_s + fraction * (b.t_s - a.t_s) - launch_t_s;
    point.xy_m = (end_a + fraction * (end_b - end_a)).head<2>();
    return point;
  }
  return std::nullopt;
}

double post_impact_energy_J(const model::PoleState& before, const Eigen::Vector3d& plate_velocity_mps,
                            const model::PoleParams& params) {
  const model::ImpactResult impact = model::impact_map(before, plate_velocity_mps, params);
  const double length = params.half_length_m;
  const double pivot_inertia = params.mass_kg * length * length + model::pole_inertia_kgm2(params);
  return params.mass_kg * params.gravity_mps2 * length * impact.after.n.z() +
         0.5 * pivot_inertia * impact.after.omega_radps.squaredNorm();
}

}  // namespace gs::adaptation
