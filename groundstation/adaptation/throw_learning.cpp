#include "groundstation/adaptation/throw_learning.hpp"

#include <algorithm>
#include <cmath>

namespace gs::adaptation {

LaunchVector launch_vector(const planning::PlanarLaunchState& s) {
  LaunchVector v;
  v << s.x_m, s.z_m, s.vx_mps, s.vz_mps, s.alpha_rad, s.alpha_dot_radps;
  return v;
}

planning::PlanarLaunchState launch_state(const LaunchVector& v) {
  return {v(0), v(1), v(2), v(3), v(4), v(5)};
}

LaunchMatrix damped_inverse(const LaunchMatrix& g, double lambda) {
  return (g.transpose() * g + lambda * LaunchMatrix::Identity()).inverse() * g.transpose();
}

ThrowCorrection learn_from_throw(const ThrowCorrection& correction, const planning::PlanarLaunchState& flown,
                                 const planning::PlanarLaunchState& planned,
                                 const ThrowLearningSettings& settings,
                                 const LaunchMatrix& inverse_sensitivity) {
  const LaunchVector error = launch_vector(flown) - launch_vector(planned);
  if (!error.allFinite()) return correction;
  LaunchVector bound;
  bound << settings.max_position_m, settings.max_position_m, settings.max_speed_mps, settings.max_speed_mps,
      settings.max_angle_rad, settings.max_rate_radps;
  // A launch this far from the plan is a failed or spoiled throw (pushed aside, a gust), not a
  // model error that repeats.
  if ((error.cwiseAbs().array() > bound.array()).any()) return correction;
  ThrowCorrection next = correction;
  next.end_shift =
      (correction.end_shift - settings.gain * inverse_sensitivity * error).cwiseMax(-bound).cwiseMin(bound);
  ++next.throws;
  return next;
}

}  // namespace gs::adaptation
