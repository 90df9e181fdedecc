// Motion-capture poses and the small geometric helpers the estimators share.
//
// A pose is a position and a unit quaternion q that turns body-frame vectors into inertial ones
// (q = ^I_B R). For a vehicle the body frame is the one of eq. (3); for the pole the body z-axis
// is the pole direction n (so n = q e_z, eq. (21)).
//
// Euler angles (eq. 3). ^B_I R = R_x(phi) R_y(theta) R_z(psi) with passive elementary rotations,
// so ^I_B R = Rz(psi) Ry(theta) Rx(phi) with the active ones: the usual aerospace zyx sequence.
// Its third row is (-sin theta, cos theta sin phi, cos theta cos phi) and its first column
// (cos psi cos theta, sin psi cos theta, -sin theta), which gives the extraction below.
#pragma once

#include <Eigen/Dense>
#include <Eigen/Geometry>

namespace gs::estimation {

struct MocapPose {
  Eigen::Vector3d p_m = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();  // inertial from body
};

struct EulerZyx {
  double phi_rad = 0.0;    // roll
  double theta_rad = 0.0;  // pitch
  double psi_rad = 0.0;    // yaw
};

// The angles of eq. (3) for a rotation ^I_B R (theta in [-pi/2, pi/2]).
EulerZyx euler_zyx_from_rotation(const Eigen::Matrix3d& inertial_from_body);
EulerZyx euler_zyx_from_quaternion(const Eigen::Quaterniond& inertial_from_body);

// The pole direction n = q e_z (the pole's body z-axis in the inertial frame).
Eigen::Vector3d pole_direction_from_quaternion(const Eigen::Quaterniond& inertial_from_body);

// True when every component is finite and |q| is within [0.5, 1.5] (the pose is then usable
// after normalising q); motion-capture glitches and parse errors fail it.
bool is_usable_pose(const MocapPose& pose);

// The angle wrapped into (-pi, pi].
double wrap_angle_rad(double angle_rad);

// An orthonormal basis (two columns) of the plane normal to the unit vector n. Measurements of
// a direction are taken in this plane (2 dof), which keeps |n| = 1 out of the filters.
Eigen::Matrix<double, 3, 2> tangent_basis(const Eigen::Vector3d& n);

// The cross-product matrix [v]x, [v]x w = v x w.
Eigen::Matrix3d cross_matrix(const Eigen::Vector3d& v);

}  // namespace gs::estimation
