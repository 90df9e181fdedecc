#include "groundstation/control/throw_frame.hpp"

#include <algorithm>
#include <cmath>

namespace gs::control {
namespace {

// The active turn by beta about z (arena vectors turned by +beta).
Eigen::Matrix3d turn(double beta_rad) {
  const double c = std::cos(beta_rad), s = std::sin(beta_rad);
  Eigen::Matrix3d a;
  a << c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0;
  return a;
}

}  // namespace

Eigen::Vector3d ThrowFrame::to_arena(const Eigen::Vector3d& frame_m) const {
  return origin_m + turn(yaw_rad) * frame_m;
}
Eigen::Vector3d ThrowFrame::to_frame(const Eigen::Vector3d& arena_m) const {
  return turn(yaw_rad).transpose() * (arena_m - origin_m);
}
Eigen::Vector2d ThrowFrame::to_arena_xy(const Eigen::Vector2d& frame_xy_m) const {
  return origin_m.head<2>() + direction_to_arena(frame_xy_m);
}
Eigen::Vector2d ThrowFrame::to_frame_xy(const Eigen::Vector2d& arena_xy_m) const {
  return turn(yaw_rad).topLeftCorner<2, 2>().transpose() * (arena_xy_m - origin_m.head<2>());
}
Eigen::Vector2d ThrowFrame::direction_to_arena(const Eigen::Vector2d& frame_xy) const {
  return turn(yaw_rad).topLeftCorner<2, 2>() * frame_xy;
}
Eigen::Vector3d ThrowFrame::direction_to_frame(const Eigen::Vector3d& arena) const {
  return turn(yaw_rad).transpose() * arena;
}

// With A the turn, the frame's coordinates are x_F = A^T (x - o) and the relabelled body's
// x_B' = A^T x_B, so ^F_B'R = A^T ^I_B R A; its zyx Euler angles (eq. (3)) keep psi and turn the
// tilt by -beta.
model::VehicleState ThrowFrame::to_frame(const model::VehicleState& arena) const {
  const Eigen::Matrix3d a = turn(yaw_rad);
  const Eigen::Matrix3d r =
      a.transpose() * model::rotation_inertial_from_body(arena.phi_rad, arena.theta_rad, arena.psi_rad) * a;
  model::VehicleState s;
  s.p_m = to_frame(arena.p_m);
  s.v_mps = a.transpose() * arena.v_mps;
  s.theta_rad = -std::asin(std::clamp(r(2, 0), -1.0, 1.0));
  s.phi_rad = std::atan2(r(2, 1), r(2, 2));
  s.psi_rad = std::atan2(r(1, 0), r(0, 0));
  return s;
}

model::PoleState ThrowFrame::to_frame(const model::PoleState& arena) const {
  const Eigen::Matrix3d at = turn(yaw_rad).transpose();
  return {to_frame(arena.p_m), at * arena.v_mps, at * arena.n, at * arena.omega_radps};
}

Pivot ThrowFrame::to_frame(const Pivot& arena) const {
  return {to_frame(arena.p_m), direction_to_frame(arena.v_mps)};
}

// omega_B = A omega_B' (the relabelled body's coordinates turned back).
Eigen::Vector3d ThrowFrame::body_rates_to_vehicle(const Eigen::Vector3d& frame_radps) const {
  return turn(yaw_rad) * frame_radps;
}

}  // namespace gs::control
