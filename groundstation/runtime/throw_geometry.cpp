#include "groundstation/runtime/throw_geometry.hpp"

#include <cmath>

#include "pa/constants.hpp"

namespace gs::runtime {

control::ThrowFrame throw_frame_of(pa::VehicleId thrower, const Eigen::Vector3d& origin_m, double yaw_rad,
                                   const adaptation::AdaptationState& adaptation) {
  const control::ThrowFrame first{origin_m, yaw_rad};
  if (thrower == pa::kVehicle1) return first;
  const Eigen::Vector2d back = first.to_arena_xy(adaptation.waiting_xy_m);
  return {Eigen::Vector3d(back.x(), back.y(), origin_m.z()), yaw_rad + M_PI};
}

Eigen::Vector2d catch_point_xy(const control::ThrowFrame& frame,
                               const adaptation::AdaptationState& adaptation,
                               const std::optional<Eigen::Vector3d>& aimed_m) {
  if (aimed_m) return aimed_m->head<2>();
  return frame.to_arena_xy(adaptation::compensate_offset_bias(adaptation.waiting_xy_m, adaptation));
}

double catch_height_m(const control::ThrowFrame& frame, const adaptation::AdaptationState& adaptation,
                      const std::optional<Eigen::Vector3d>& aimed_m, double energy_offset_m) {
  if (aimed_m) return aimed_m->z() + energy_offset_m;
  return frame.origin_m.z() + adaptation.catch_height_m + energy_offset_m;
}

Eigen::Vector3d throw_start_m(const control::ThrowFrame& frame) {
  return frame.origin_m - pa::kPlateHeightAboveCg_m * Eigen::Vector3d::UnitZ();
}

}  // namespace gs::runtime
