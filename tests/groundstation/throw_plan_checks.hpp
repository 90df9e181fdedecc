// What the throw planner's tests recompute from a returned trajectory, independently of the
// collocation NLP (throw_planner_test, target_throw_test).
#pragma once

#include <algorithm>
#include <catch2/catch.hpp>

#include "groundstation/planning/throw_trajectory.hpp"

namespace throw_checks {

// The largest Simpson defect s_b - s_a - h/6 (f_a + 4 f_m + f_b) and Hermite midpoint defect
// s_m - (s_a + s_b)/2 - h/8 (f_a - f_b) over the intervals, with f from the planar model; checks
// on the way that each midpoint sits halfway between its knots.
inline double max_collocation_defect(const gs::planning::ThrowTrajectory& traj) {
  double worst = 0.0;
  for (int k = 0; k < traj.intervals(); ++k) {
    const int a = 2 * k, m = 2 * k + 1, b = 2 * k + 2;
    const double h = traj.t_s[b] - traj.t_s[a];
    CHECK(traj.t_s[m] == Approx(0.5 * (traj.t_s[a] + traj.t_s[b])));
    const auto f = [&](int j) {
      return gs::model::planar_pole_vehicle_dynamics<double>(traj.state[j], traj.input[j], traj.params);
    };
    const gs::model::PlanarState<double> simpson =
        traj.state[b] - traj.state[a] - h / 6.0 * (f(a) + 4.0 * f(m) + f(b));
    const gs::model::PlanarState<double> hermite =
        traj.state[m] - 0.5 * (traj.state[a] + traj.state[b]) - h / 8.0 * (f(a) - f(b));
    worst = std::max({worst, simpson.cwiseAbs().maxCoeff(), hermite.cwiseAbs().maxCoeff()});
  }
  return worst;
}

}  // namespace throw_checks
