#include "groundstation/control/task_laws.hpp"

#include <algorithm>
#include <cmath>

#include "groundstation/control/balancing_lqr.hpp"
#include "groundstation/control/hover_lqr.hpp"

namespace gs::control {

// The set point's velocity is the controllers' velocity reference: a set point that jumped
// along at constant speed with a zero velocity reference made the vehicle lag it and overshoot
// by 0.08 m after a 1 m move to the waiting point (measured, the paper's series).
void move_set_point(SetPoint& set_point, const Eigen::Vector3d& target_m, const Eigen::Vector3d& position_m,
                    double dt_s, const CarrotLimits& limits) {
  if (!set_point.valid) {
    set_point.position_m = position_m;
    set_point.velocity_mps.setZero();
    set_point.valid = true;
  }
  const Eigen::Vector3d to_go = target_m - set_point.position_m;
  const double distance = to_go.norm();
  if (distance < 1e-9) {
    set_point.velocity_mps.setZero();
    return;
  }
  const Eigen::Vector3d direction = to_go / distance;
  const double a = limits.acceleration_mps2;
  const double speed = std::min({std::max(0.0, set_point.velocity_mps.dot(direction)) + a * dt_s,
                                 limits.speed_mps, std::sqrt(2.0 * a * distance)});
  if (speed * dt_s >= distance) {
    set_point.position_m = target_m;
    set_point.velocity_mps.setZero();
  } else {
    set_point.position_m += speed * dt_s * direction;
    set_point.velocity_mps = speed * direction;
  }
}

// The integral learns constant force offsets (thrust mismatch, drag, the pole's weight) at rest
// only: integrating the lag behind a moving set point wound it up, and a 1 m move to the
// waiting point overshot by 0.17 m and crept back for seconds, so the catch started from
// elsewhere (measured, the paper's series, throw 8).
void integrate_position_error(Eigen::Vector3d& integral_ms, const SetPoint& set_point,
                              const Eigen::Vector3d& target_m, const Eigen::Vector3d& position_m, double dt_s,
                              double limit_ms) {
  if ((target_m - set_point.position_m).norm() > 1e-9) return;
  integral_ms += (set_point.position_m - position_m) * dt_s;
  integral_ms = integral_ms.cwiseMax(-limit_ms).cwiseMin(limit_ms);
}

model::VehicleInput hover_law(const LqrGain& hover_gain, const model::VehicleState& vehicle,
                              const HoverReference& reference) {
  namespace hv = hover;
  Eigen::VectorXd x = hover_state(vehicle, reference.position_m);
  x.segment<3>(hv::kVx) -= reference.velocity_mps;
  x(hv::kRoll) -= reference.roll_rad;
  x(hv::kPitch) -= reference.pitch_rad;
  x(hv::kYaw) -= reference.yaw_rad;
  const Eigen::VectorXd du = -hover_gain.K * x;
  model::VehicleInput u;
  u.a_q_mps2 = reference.thrust_mps2 + du(hv::kThrust);
  u.omega_radps = reference.body_rates_radps + du.segment<3>(hv::kRateX);
  return u;
}

model::VehicleInput balance_law(const LqrGain& balancing_gain, const Pivot& pivot,
                                const model::VehicleState& vehicle, const model::PoleState& pole,
                                double half_length_m, const Eigen::Vector3d& set_point_m,
                                const Eigen::Vector3d& set_point_velocity_mps, double pole_weight_mps2) {
  namespace bal = balancing;
  Eigen::VectorXd x = balancing_state(pivot, vehicle, pole, half_length_m, set_point_m);
  x.segment<3>(bal::kVx) -= set_point_velocity_mps;
  Eigen::VectorXd u = -balancing_gain.K * x;
  u(bal::kThrust) += pa::kGravity_mps2 + pole_weight_mps2;
  return from_balancing_input(u);
}

model::VehicleInput release_law(const model::VehicleState& vehicle, double since_s, double pitch_s,
                                const Eigen::Vector3d& pitch_rates_radps, double level_gain_per_s,
                                double thrust_mps2) {
  model::VehicleInput u;
  u.a_q_mps2 = thrust_mps2;
  u.omega_radps = since_s < pitch_s ? pitch_rates_radps
                                    : Eigen::Vector3d(-level_gain_per_s * vehicle.phi_rad,
                                                      -level_gain_per_s * vehicle.theta_rad, 0.0);
  return u;
}

model::VehicleInput limit_tilt(model::VehicleInput u, const model::VehicleState& vehicle,
                               const TiltLimit& limit) {
  // Roll and pitch follow the body rates about x and y closely at these tilts with little yaw
  // rate, so each axis is limited on its own: towards the limit at most gain (limit - angle),
  // so the tilt approaches the limit with time constant 1 / gain instead of overshooting it by
  // the rate loop's and the motors' lag.
  const auto limit_axis = [&](double angle_rad, double& rate_radps) {
    rate_radps = std::clamp(rate_radps, -limit.gain_per_s * (limit.max_tilt_rad + angle_rad),
                            limit.gain_per_s * (limit.max_tilt_rad - angle_rad));
  };
  limit_axis(vehicle.phi_rad, u.omega_radps.x());
  limit_axis(vehicle.theta_rad, u.omega_radps.y());
  return u;
}

model::VehicleInput clamp_input(model::VehicleInput u, const model::VehicleLimits& limits) {
  u.a_q_mps2 = std::clamp(u.a_q_mps2, limits.a_q_min_mps2, limits.a_q_max_mps2);
  for (int i = 0; i < 3; ++i)
    u.omega_radps(i) = std::clamp(u.omega_radps(i), -limits.omega_max_radps, limits.omega_max_radps);
  return u;
}

}  // namespace gs::control
