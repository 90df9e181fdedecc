// The laws the runtime flies its tasks with, as functions of the latency-compensated state and
// a reference (Section VII-A flies every controller on the estimator's state): the set point
// that moves towards a task's target (the carrot), the position integral, the hover law with
// optional feed-forward (hover, waiting, the catch manoeuvre's tracking), the balancing law, the
// release and the input clamp. No state of their own beyond what the caller passes in.
#pragma once

#include <Eigen/Core>

#include "groundstation/control/controller_states.hpp"
#include "groundstation/control/lqr.hpp"
#include "groundstation/model/vehicle.hpp"
#include "groundstation/model/vehicle_limits.hpp"

namespace gs::control {

// A set point and its velocity: the controllers' position and velocity reference.
struct SetPoint {
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_mps = Eigen::Vector3d::Zero();
  bool valid = false;
};

struct CarrotLimits {
  double speed_mps = 1.0;
  double acceleration_mps2 = 1.0;
};

// Moves the set point towards `target_m` with a trapezoidal speed profile (accelerating,
// cruising, braking to stop on it); an invalid set point starts at `position_m` at rest. The
// linear LQRs then only ever see small position errors.
void move_set_point(SetPoint& set_point, const Eigen::Vector3d& target_m, const Eigen::Vector3d& position_m,
                    double dt_s, const CarrotLimits& limits);

// Integrates the position error (set point - position) at rest only, each axis clamped to
// +-limit_ms (m s): while the set point moves the vehicle lags it by design.
void integrate_position_error(Eigen::Vector3d& integral_ms, const SetPoint& set_point,
                              const Eigen::Vector3d& target_m, const Eigen::Vector3d& position_m, double dt_s,
                              double limit_ms);

// The hover LQR's reference: a point (the set point shifted by the integral), its velocity and,
// for a time-varying reference such as the catch manoeuvre, the attitude and the nominal inputs
// (46), (47) as feed-forward.
struct HoverReference {
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_mps = Eigen::Vector3d::Zero();
  double roll_rad = 0.0, pitch_rad = 0.0, yaw_rad = 0.0;
  double thrust_mps2 = pa::kGravity_mps2;
  Eigen::Vector3d body_rates_radps = Eigen::Vector3d::Zero();
};
model::VehicleInput hover_law(const LqrGain& hover, const model::VehicleState& vehicle,
                              const HoverReference& reference);

// The balancing LQR about `set_point_m` (where the pivot should be) moving at
// `set_point_velocity_mps`, the pole's weight `pole_weight_mps2` carried as feed-forward.
model::VehicleInput balance_law(const LqrGain& balancing, const Pivot& pivot,
                                const model::VehicleState& vehicle, const model::PoleState& pole,
                                double half_length_m, const Eigen::Vector3d& set_point_m,
                                const Eigen::Vector3d& set_point_velocity_mps, double pole_weight_mps2);

// After the throw (Section VII-A leaves it open): `thrust_mps2` (the minimum), the plate
// pitching back at `pitch_rates_radps` (body rates, vehicle frame) for `pitch_s`, then roll and
// pitch levelled at `level_gain_per_s`.
model::VehicleInput release_law(const model::VehicleState& vehicle, double since_s, double pitch_s,
                                const Eigen::Vector3d& pitch_rates_radps, double level_gain_per_s,
                                double thrust_mps2);

// A vehicle balancing a pole it cannot hold: the LQR asks the tilt the pole needs, and a pole
// landing with too much energy needs more than the vehicle can fly (measured on the arena
// envelope: after such a catch the catcher's pitch rate sat at its 10 rad/s limit for 0.15 s,
// the vehicle rolled over and fell). The roll and pitch rates are bounded so that the tilt
// approaches `max_tilt_rad` at `gain_per_s` and never passes it (beyond it, the bound brings it
// back): the pole may be lost, the vehicle is not. Level, the bound is 7 rad/s, more than a
// balanced pole asks.
struct TiltLimit {
  double max_tilt_rad = 0.7;
  double gain_per_s = 10.0;
};
model::VehicleInput limit_tilt(model::VehicleInput u, const model::VehicleState& vehicle,
                               const TiltLimit& limit);

// The inputs within the vehicle's limits (1), (2).
model::VehicleInput clamp_input(model::VehicleInput u, const model::VehicleLimits& limits);

}  // namespace gs::control
