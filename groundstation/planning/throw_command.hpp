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
                                  const Eigen::VectorXd& balancing_state, const model::VehicleLimits& limits,
                                  double feedforward_lead_s = 0.0);

// s_qp with the throw plane's components (x, z, vx, vz, pitch, a, a') set to zero: what the
// lateral balancing sees.
Eigen::VectorXd lateral_balancing_state(const Eigen::VectorXd& balancing_state);

// One step of a throw flown on the arena's estimate (what the runtime does at each frame of the
// throwing task): the plate, the vehicle and the pole turned into the throw's frame, the planar
// state fed to the TV-LQR shifted against `reference_shift` (the learnt throw, zero for none),
// the pole flown about its resting end, `resting_offset_m` from the plate's centre (arena axes),
// in the plane and across it, and the body rates turned back to the vehicle's. About the centre, a
// pole resting 1-2 cm off it reads as a tilt: across the plane the lateral LQR flew it as a
// sideways push (passes drifted sideways until one was dropped, hil fly --passes 100 --randomise
// seeds 1 and 4: 37 and 7 passes, then 84 and 92); in the plane the TV-LQR flew it off, the launch
// x falling short by about 13 times the offset along the throw (0.5 m at 3.8 cm, seed 5's
// passes after a catch; full batteries' 100 passes: 76 in a row, then all 100).
//
// `feedforward_lead_s`: how much longer than the design's the vehicle's motors lag (identified).
// The firmware's equaliser makes a slow motor respond as the design's with a lead-lag
// (fw/motor_lag_equaliser.hpp), except where the lead saturates: at the throw's end the plan cuts
// the thrust from ~23 m/s^2 to its minimum within 50 ms, the lead asks for less than nothing, and
// the thrust falls at the motor's own pace, pushing the pole on for the lag's difference. The pole
// left faster and turning more, its (42) up to 1.5 m above the learnt catch (envelope attempts with
// a 50-60 ms thrower: 56 % and 32 % caught against 85 % below 35 ms, `hil campaign --attempts 1000
// --plant hil/config/envelope.yaml`). Read that much ahead, the plan's feed-forward cuts the thrust
// that much earlier; elsewhere the plan's inputs change slowly (~13 m/s^3 of thrust while it
// climbs: 0.35 m/s^2 over 27 ms), which the feedback absorbs.
struct ThrowStep {
  model::VehicleInput input;         // clamped as throw_command()'s
  model::PlanarState<double> state;  // the throw's planar state, unshifted
};
ThrowStep throw_step(const ThrowTracker& tracker, const control::LqrGain& balancing, double t_s,
                     const control::ThrowFrame& frame, const control::Pivot& plate,
                     const Eigen::Vector3d& resting_offset_m, const model::VehicleState& vehicle,
                     const model::PoleState& pole, double half_length_m,
                     const model::PlanarState<double>& reference_shift, const model::VehicleLimits& limits,
                     double feedforward_lead_s = 0.0);

}  // namespace gs::planning
