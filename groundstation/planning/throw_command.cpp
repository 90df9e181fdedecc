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
                                  const Eigen::VectorXd& balancing_state, const model::VehicleLimits& limits,
                                  double feedforward_lead_s) {
  namespace bal = control::balancing;
  const model::PlanarInput<double> planar =
      saturate(tracker.command(t_s, planar_state, feedforward_lead_s), limits);
  const Eigen::VectorXd lateral = -balancing.K * lateral_balancing_state(balancing_state);
  const double omega_max = limits.omega_max_radps;
  model::VehicleInput u;
  u.a_q_mps2 = planar(model::planar::kThrust);
  u.omega_radps = Eigen::Vector3d(std::clamp(lateral(bal::kRateX), -omega_max, omega_max),
                                  planar(model::planar::kPitchRate),
                                  std::clamp(lateral(bal::kRateZ), -omega_max, omega_max));
  return u;
}

ThrowStep throw_step(const ThrowTracker& tracker, const control::LqrGain& balancing, double t_s,
                     const control::ThrowFrame& frame, const control::Pivot& plate,
                     const Eigen::Vector3d& resting_offset_m, const model::VehicleState& vehicle,
                     const model::PoleState& pole, double half_length_m,
                     const model::PlanarState<double>& reference_shift, const model::VehicleLimits& limits,
                     double feedforward_lead_s) {
  const control::Pivot resting = frame.to_frame(control::Pivot{plate.p_m + resting_offset_m, plate.v_mps});
  const model::VehicleState vehicle_in_frame = frame.to_frame(vehicle);
  const model::PoleState pole_in_frame = frame.to_frame(pole);
  ThrowStep step;
  step.state = control::planar_throw_state(resting, vehicle_in_frame, pole_in_frame, Eigen::Vector3d::Zero());
  const Eigen::VectorXd b = control::balancing_state(resting, vehicle_in_frame, pole_in_frame, half_length_m,
                                                     Eigen::Vector3d::Zero());
  step.input =
      throw_command(tracker, balancing, t_s, step.state - reference_shift, b, limits, feedforward_lead_s);
  step.input.omega_radps = frame.body_rates_to_vehicle(step.input.omega_radps);
  return step;
}

}  // namespace gs::planning
