// How far a throw reaches, in its frame (x along the throw, z up, the origin at the thrower's
// centre before it): the box around the thrower's path over the plan and the pole's highest
// point after the launch. The arena's volume is checked against it before a throw is flown
// (runtime/attempt_admission.hpp).
//
// The pole's centre rises from the launch state (eqs. 23, 26) as without drag, which only lowers
// it, and its ends are at most L from its centre: the reach is an upper bound on the ceiling
// the throw needs, not a prediction of the flight.
#pragma once

#include <Eigen/Core>

#include "groundstation/model/pole_free_flight.hpp"
#include "groundstation/planning/throw_trajectory.hpp"

namespace gs::planning {

struct ThrowReach {
  Eigen::Vector3d min_m = Eigen::Vector3d::Zero();  // in the throw's frame
  Eigen::Vector3d max_m = Eigen::Vector3d::Zero();
  double pole_apex_m = 0.0;  // the highest any point of the pole can reach (frame z)
};

// The reach of `trajectory` (at least one point) with a pole of `pole`'s length.
ThrowReach throw_reach(const ThrowTrajectory& trajectory, const model::PoleParams& pole);

}  // namespace gs::planning
