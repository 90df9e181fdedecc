// The throw's frame: the planar throw (34) and its TV-LQR live in the x-z plane with the throw
// towards +x from the origin. A throw in any horizontal direction beta is the same throw seen
// from a frame turned by beta about the vertical through the throw's origin. The vehicle need
// not yaw for it: its body axes are relabelled by the same turn about its own z (the thrust, the
// rate loop and the model are symmetric about body z: roll and pitch are flown alike on board),
// so a level vehicle keeps its yaw in the throw's frame (a tilted one to second order in the
// tilt), and its tilt turns by -beta.
// States go into the frame (to_frame), the controllers' body rates come back out
// (body_rates_to_vehicle). Pure functions of the frame.
#pragma once

#include <Eigen/Core>

#include "groundstation/control/controller_states.hpp"
#include "groundstation/model/pole_free_flight.hpp"
#include "groundstation/model/vehicle.hpp"

namespace gs::control {

struct ThrowFrame {
  Eigen::Vector3d origin_m = Eigen::Vector3d::Zero();  // the thrower's plate centre before the throw
  double yaw_rad = 0.0;                                // the throw's direction, from +x towards +y

  // Arena coordinates of a point given in the frame, and back.
  Eigen::Vector3d to_arena(const Eigen::Vector3d& frame_m) const;
  Eigen::Vector3d to_frame(const Eigen::Vector3d& arena_m) const;
  // The same for horizontal points (x, y) and for directions (no origin).
  Eigen::Vector2d to_arena_xy(const Eigen::Vector2d& frame_xy_m) const;
  Eigen::Vector2d to_frame_xy(const Eigen::Vector2d& arena_xy_m) const;
  Eigen::Vector2d direction_to_arena(const Eigen::Vector2d& frame_xy) const;
  Eigen::Vector3d direction_to_frame(const Eigen::Vector3d& arena) const;

  // A vehicle's state (6), the pole's and the plate's as the throw's frame sees them.
  model::VehicleState to_frame(const model::VehicleState& arena) const;
  model::PoleState to_frame(const model::PoleState& arena) const;
  Pivot to_frame(const Pivot& arena) const;
  // Body rates commanded in the frame's relabelled body axes, in the vehicle's own.
  Eigen::Vector3d body_rates_to_vehicle(const Eigen::Vector3d& frame_radps) const;
};

}  // namespace gs::control
