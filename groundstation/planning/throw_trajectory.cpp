#include "groundstation/planning/throw_trajectory.hpp"

#include <algorithm>

namespace gs::planning {
namespace {

struct Locator {
  int knot;    // index of the interval's first knot in the point vectors (even)
  double tau;  // position in the interval, [0, 1]
  double h;    // interval length
};

Locator locate(const ThrowTrajectory& traj, double t_s) {
  const int n = traj.intervals();
  const double t = std::clamp(t_s, traj.t_s.front(), traj.t_s.back());
  // Knots are the even entries; find the last knot at or before t (intervals may differ).
  int lo = 0, hi = n - 1;
  while (lo < hi) {
    const int mid = (lo + hi + 1) / 2;
    if (traj.t_s[2 * mid] <= t) lo = mid;
    else hi = mid - 1;
  }
  const double t_k = traj.t_s[2 * lo];
  const double h_k = traj.t_s[2 * lo + 2] - t_k;
  return {2 * lo, std::clamp((t - t_k) / h_k, 0.0, 1.0), h_k};
}

}  // namespace

model::PlanarState<double> ThrowTrajectory::state_at(double t) const {
  const Locator at = locate(*this, t);
  const model::PlanarState<double>& s0 = state[at.knot];
  const model::PlanarState<double>& s1 = state[at.knot + 2];
  const model::PlanarState<double> f0 =
      model::planar_pole_vehicle_dynamics<double>(s0, input[at.knot], params);
  const model::PlanarState<double> f1 =
      model::planar_pole_vehicle_dynamics<double>(s1, input[at.knot + 2], params);
  const double tau = at.tau, tau2 = tau * tau, tau3 = tau2 * tau;
  const double h00 = 2.0 * tau3 - 3.0 * tau2 + 1.0;
  const double h10 = tau3 - 2.0 * tau2 + tau;
  const double h01 = -2.0 * tau3 + 3.0 * tau2;
  const double h11 = tau3 - tau2;
  return h00 * s0 + (h10 * at.h) * f0 + h01 * s1 + (h11 * at.h) * f1;
}

model::PlanarInput<double> ThrowTrajectory::input_at(double t) const {
  const Locator at = locate(*this, t);
  const double tau = at.tau;
  // Lagrange basis on the nodes 0, 1/2, 1.
  const double l0 = 2.0 * (tau - 0.5) * (tau - 1.0);
  const double lm = -4.0 * tau * (tau - 1.0);
  const double l1 = 2.0 * tau * (tau - 0.5);
  return l0 * input[at.knot] + lm * input[at.knot + 1] + l1 * input[at.knot + 2];
}

}  // namespace gs::planning
