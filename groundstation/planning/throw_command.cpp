#include "groundstation/planning/throw_command.hpp"

#include <algorithm>

#include "groundstation/control/balancing_lqr.hpp"

namespace gs::planning {

Eigen::VectorXd lateral_balancing_state(const Eigen::VectorXd& balancing_state) {
  namespace bal = control::balancing;
  Eigen::VectorXd lateral = balancing_state;
  for (int i : {bal::kX, bal::kZ, bal::kVx, bal::kVz, bal::kPitch, bal::kA, bal::kADot}) {
    lateral(i) = 0.0;
  }
  return lateral;
}

model::VehicleInput throw_command(const ThrowTracker& tracker, const control::LqrGain& balancing, double t_s,
                                  const model::PlanarState<double>& planar_state,
                                  const Eigen::VectorXd& balancing_state,
                                  const model::VehicleLimits& limits) {
  namespace bal = control::balancing;
  const model::PlanarInput<double> planar = saturate(tracker.command(t_s, planar_state), limits);
  const Eigen::VectorXd lateral = -balancing.K * lateral_balancing_state(balancing_state);
  const double omega_max = limits.omega_max_radps;
  model::VehicleInput u;
  u.a_q_mps2 = planar(model::planar::kThrust);
  u.omega_radps = Eigen::Vector3d(std::clamp(lateral(bal::kRateX), -omega_max, omega_max),
                                  planar(model::planar::kPitchRate),
                                  std::clamp(lateral(bal::kRateZ), -omega_max, omega_max));
  return u;
}

}  // namespace gs::planning
