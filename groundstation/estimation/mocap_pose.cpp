#include "groundstation/estimation/mocap_pose.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace gs::estimation {

EulerZyx euler_zyx_from_rotation(const Eigen::Matrix3d& r) {
  EulerZyx e;
  e.theta_rad = -std::asin(std::clamp(r(2, 0), -1.0, 1.0));
  e.phi_rad = std::atan2(r(2, 1), r(2, 2));
  e.psi_rad = std::atan2(r(1, 0), r(0, 0));
  return e;
}

EulerZyx euler_zyx_from_quaternion(const Eigen::Quaterniond& q) {
  return euler_zyx_from_rotation(q.normalized().toRotationMatrix());
}

Eigen::Vector3d pole_direction_from_quaternion(const Eigen::Quaterniond& q) {
  return q.normalized() * Eigen::Vector3d::UnitZ();
}

bool is_usable_pose(const MocapPose& pose) {
  if (!pose.p_m.allFinite() || !pose.q.coeffs().allFinite()) return false;
  const double norm = pose.q.norm();
  return norm >= 0.5 && norm <= 1.5;
}

double wrap_angle_rad(double angle_rad) {
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  double a = std::fmod(angle_rad + std::numbers::pi, kTwoPi);
  if (a <= 0.0) a += kTwoPi;
  return a - std::numbers::pi;
}

Eigen::Matrix<double, 3, 2> tangent_basis(const Eigen::Vector3d& n) {
  // Cross with the axis least aligned with n: well conditioned for every n.
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();
  const Eigen::Vector3d a = n.cwiseAbs();
  if (a.y() <= a.x() && a.y() <= a.z()) axis = Eigen::Vector3d::UnitY();
  if (a.z() <= a.x() && a.z() <= a.y()) axis = Eigen::Vector3d::UnitZ();
  Eigen::Matrix<double, 3, 2> b;
  b.col(0) = n.cross(axis).normalized();
  b.col(1) = n.cross(b.col(0)).normalized();
  return b;
}

Eigen::Matrix3d cross_matrix(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

}  // namespace gs::estimation
