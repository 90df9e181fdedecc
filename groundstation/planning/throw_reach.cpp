#include "groundstation/planning/throw_reach.hpp"

#include <algorithm>

#include "groundstation/planning/catching_instant.hpp"

namespace gs::planning {

ThrowReach throw_reach(const ThrowTrajectory& trajectory, const model::PoleParams& pole) {
  ThrowReach reach;
  if (trajectory.state.empty()) return reach;
  const auto at = [](const model::PlanarState<double>& s) {
    return Eigen::Vector3d(s(model::planar::kX), 0.0, s(model::planar::kZ));
  };
  reach.min_m = reach.max_m = at(trajectory.state.front());
  for (const model::PlanarState<double>& s : trajectory.state) {
    reach.min_m = reach.min_m.cwiseMin(at(s));
    reach.max_m = reach.max_m.cwiseMax(at(s));
  }
  const model::PoleState p = pole_state_at_launch(launch_state_of(trajectory.state.back()), pole);
  // The centre's drag-free apex, reached after vz / g; the pole's end up to L above it.
  const double rise_s = std::max(p.v_mps.z(), 0.0) / pole.gravity_mps2;
  const Eigen::Vector3d apex =
      p.p_m + p.v_mps * rise_s - 0.5 * pole.gravity_mps2 * rise_s * rise_s * Eigen::Vector3d::UnitZ();
  reach.pole_apex_m = apex.z() + pole.half_length_m;
  reach.min_m = reach.min_m.cwiseMin(apex - pole.half_length_m * Eigen::Vector3d::Ones());
  reach.max_m = reach.max_m.cwiseMax(apex + pole.half_length_m * Eigen::Vector3d::Ones());
  return reach;
}

}  // namespace gs::planning
