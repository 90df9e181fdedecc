// The vehicle command while a throw is tracked, in 3D (Section VII-A flies the throw with a
// time-varying LQR on the planar model; the vehicle and the pole move in 3D).
//
// In the throw's plane (x-z) the planar TV-LQR (throw_tracking.hpp) gives the collective thrust
// and the pitch rate. Across the plane the pole is balanced as in hover: the balancing LQR's
// roll- and yaw-rate rows (balancing_lqr.hpp) fed only the lateral states (y, vy, roll, yaw and
// the pole's sideways deflection b, b'), which its hover linearisation decouples from the plane.
// The planar plan says nothing about that axis, and the pole's sideways tilt is as unstable as its
// tilt in the plane (b'' = (3 a_q / 4L) b + ..., faster still at the throw's high thrust): flown
// through the firmware with the planar command alone, IMU noise grew it into a sideways fall
// and the pole left the plate 84 ms before T (tests/groundstation/throw_through_firmware_test.cpp).
#pragma once

#include <Eigen/Core>

#include "groundstation/control/controller_states.hpp"
#include "groundstation/control/lqr.hpp"
#include "groundstation/control/throw_frame.hpp"
#include "groundstation/model/vehicle.hpp"
#include "groundstation/model/vehicle_limits.hpp"
#include "groundstation/planning/throw_tracking.hpp"

namespace gs::planning {

// `planar_state` is the throw's state (planar_pole_vehicle.hpp) and `balancing_state` s_qp of
// eq. (31) (balancing_lqr.hpp order), both relative to the plan's origin at plan time t_s;
// `balancing` the balancing LQR (balancing_lqr()). The thrust and the rates are clamped into the
// box of eq. (1), (2). Precondition: tracker.valid(), balancing.K is 4 x 13.
model::VehicleInput throw_command(const ThrowTracker& tracker, const control::LqrGain& balancing, double t_s,
                                  const model::PlanarState<double>& planar_state,
                                  const Eigen::VectorXd& balancing_state, const model::VehicleLimits& limits);

// s_qp with the throw plane's components (x, z, vx, vz, pitch, a, a') set to zero: what the
// lateral balancing sees.
Eigen::VectorXd lateral_balancing_state(const Eigen::VectorXd& balancing_state);

// One step of a throw flown on the arena's estimate (what the runtime does at each frame of the
// throwing task): the plate, the vehicle and the pole turned into the throw's frame, the planar
// state fed to the TV-LQR shifted against `reference_shift` (the learnt throw, zero for none),
// the pole balanced across the plane about its resting end `resting_offset_m` from the plate's
// centre (arena frame: about the centre, a pole resting 1-2 cm off it reads as a tilt, which the
// lateral LQR flies as a sideways push), and the body rates turned back to the vehicle's.
struct ThrowStep {
  model::VehicleInput input;         // clamped as throw_command()'s
  model::PlanarState<double> state;  // the throw's planar state, unshifted
};
ThrowStep throw_step(const ThrowTracker& tracker, const control::LqrGain& balancing, double t_s,
                     const control::ThrowFrame& frame, const control::Pivot& plate,
                     const Eigen::Vector3d& resting_offset_m, const model::VehicleState& vehicle,
                     const model::PoleState& pole, double half_length_m,
                     const model::PlanarState<double>& reference_shift, const model::VehicleLimits& limits);

}  // namespace gs::planning
