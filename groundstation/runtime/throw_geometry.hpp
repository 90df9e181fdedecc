// Where an attempt flies in the arena: each thrower's throw frame, the catch point and height
// expected for the next throw, and where the thrower starts. The adaptation's values are the
// throw's, in its frame (adaptation/adaptation_law.hpp); the runtime flies in the arena's. A
// throw to a target comes down on the point its plan aimed at. Pure (throw_geometry_test.cpp).
#pragma once

#include <optional>

#include <Eigen/Core>

#include "groundstation/adaptation/adaptation_law.hpp"
#include "groundstation/control/throw_frame.hpp"
#include "pa/vehicle_id.hpp"

namespace gs::runtime {

// Vehicle 1 throws from `origin_m` towards `yaw_rad`. Vehicle 2 throws back: from where vehicle
// 1's throws come down (the adapted catch point, at the origin's height), the other way, so that
// passes go back and forth between two points.
control::ThrowFrame throw_frame_of(pa::VehicleId thrower, const Eigen::Vector3d& origin_m, double yaw_rad,
                                   const adaptation::AdaptationState& adaptation);

// The catch point (the pole's lower end, x y) expected for the next throw in `frame`: the adapted
// one with the offset bias compensated, or the target aimed at.
Eigen::Vector2d catch_point_xy(const control::ThrowFrame& frame,
                               const adaptation::AdaptationState& adaptation,
                               const std::optional<Eigen::Vector3d>& aimed_m);

// The catching height (lower pole end) for the next throw: the adapted one above the frame's
// origin, or the target's, corrected by the catcher's `energy_offset_m` (adaptation/catch_energy.hpp).
double catch_height_m(const control::ThrowFrame& frame, const adaptation::AdaptationState& adaptation,
                      const std::optional<Eigen::Vector3d>& aimed_m, double energy_offset_m);

// Where the thrower's centre of gravity hovers before the throw: the plate's centre at the origin.
Eigen::Vector3d throw_start_m(const control::ThrowFrame& frame);

}  // namespace gs::runtime
