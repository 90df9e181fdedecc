// The controllers' states from an estimate (Section VII-A flies every controller on the
// estimator's state): what the hover LQR, the balancing LQR and the throw's TV-LQR take, built
// from a vehicle's state (6), its plate and the pole's free-flight style state (p, v, n, Omega),
// all relative to the controller's set point. The runtime passes the estimator's
// latency-compensated state; tests may pass anything of the same shape. Pure functions.
#pragma once

#include <Eigen/Core>

#include "groundstation/model/planar_pole_vehicle.hpp"
#include "groundstation/model/pole_free_flight.hpp"
#include "groundstation/model/vehicle.hpp"

namespace gs::control {

// The catching plate's centre and velocity: the pivot the pole rests on (eq. (23)).
struct Pivot {
  Eigen::Vector3d p_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_mps = Eigen::Vector3d::Zero();
};

// s_q (eq. (6), hover_lqr.hpp order) of the vehicle's centre relative to `set_point_m`.
Eigen::VectorXd hover_state(const model::VehicleState& vehicle, const Eigen::Vector3d& set_point_m);

// s_qp (eq. (31), balancing_lqr.hpp order) relative to `set_point_m` (where the pivot should
// be): the pivot and its velocity, the Euler angles, and the pole's deflection L n = (a, b, c)
// (eq. (24)) with its rate L (Omega x n).
Eigen::VectorXd balancing_state(const Pivot& pivot, const model::VehicleState& vehicle,
                                const model::PoleState& pole, double half_length_m,
                                const Eigen::Vector3d& set_point_m);

// The throw's planar state (planar_pole_vehicle.hpp) in the x-z plane through `origin_m`:
// the pivot, the thrust axis's pitch theta, the pole's tilt alpha from the vertical towards +x
// and its rate.
model::PlanarState<double> planar_throw_state(const Pivot& pivot, const model::VehicleState& vehicle,
                                              const model::PoleState& pole, const Eigen::Vector3d& origin_m);

}  // namespace gs::control
