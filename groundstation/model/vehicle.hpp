// The quadrocopter model of Section II-A, eq. (1)-(8): a rigid body whose inputs are the
// mass-normalised collective thrust a_q along the body z-axis and the body rates Omega_q, tracked
// on board by a high-bandwidth rate loop so that the rotational dynamics are neglected.
//
// Conventions (docs/paper-notes.md): inertial frame z up, gravity (0, 0, -g); zyx Euler angles
// (yaw psi, pitch theta, roll phi) with ^B_I R = R_x(phi) R_y(theta) R_z(psi) (eq. 3), each
// R_(.) the passive (frame) rotation, so that the thrust direction ^I_B R e_z is
// (sin theta, 0, cos theta) for phi = psi = 0: the planar model's (sin theta, cos theta).
#pragma once

#include <Eigen/Dense>

#include "pa/constants.hpp"

namespace gs::model {

// s_q = (p_q, p_q', phi, theta, psi), eq. (6). The same struct carries the time derivative
// f_q(s_q, u_q) of eq. (8), each field then holding the rate of that field.
struct VehicleState {
  Eigen::Vector3d p_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_mps = Eigen::Vector3d::Zero();
  double phi_rad = 0.0;    // roll
  double theta_rad = 0.0;  // pitch
  double psi_rad = 0.0;    // yaw
};

VehicleState operator+(const VehicleState& lhs, const VehicleState& rhs);
VehicleState operator*(double scale, const VehicleState& state);

// u_q = (a_q, Omega_q), eq. (7).
struct VehicleInput {
  double a_q_mps2 = pa::kGravity_mps2;
  Eigen::Vector3d omega_radps = Eigen::Vector3d::Zero();  // body rates (x, y, z)
};

// The elementary passive rotations of eq. (3).
Eigen::Matrix3d rotation_x(double angle_rad);
Eigen::Matrix3d rotation_y(double angle_rad);
Eigen::Matrix3d rotation_z(double angle_rad);

// An attitude's Euler angles with their sines and cosines, evaluated once for the several
// rotations and rate maps of (3)-(5) at that attitude (the ground station's observers need them
// a few times a step). Each function gives the same numbers from it as from the angles.
struct EulerTrig {
  EulerTrig(double phi_rad, double theta_rad, double psi_rad);
  double phi_rad, theta_rad, psi_rad;
  double sin_phi, cos_phi, sin_theta, cos_theta, sin_psi, cos_psi;
};

// ^B_I R (eq. 3): maps inertial coordinates into body coordinates.
Eigen::Matrix3d rotation_body_from_inertial(double phi_rad, double theta_rad, double psi_rad);
Eigen::Matrix3d rotation_body_from_inertial(const EulerTrig& attitude);
// ^I_B R, its inverse (transpose).
Eigen::Matrix3d rotation_inertial_from_body(double phi_rad, double theta_rad, double psi_rad);
Eigen::Matrix3d rotation_inertial_from_body(const EulerTrig& attitude);

// Body rates from Euler rates: the matrix printed in eq. (5), Omega = W (phi', theta', psi').
Eigen::Vector3d body_rates_from_euler_rates(double phi_rad, double theta_rad,
                                            const Eigen::Vector3d& euler_rates_radps);
Eigen::Vector3d body_rates_from_euler_rates(const EulerTrig& attitude,
                                            const Eigen::Vector3d& euler_rates_radps);
// Euler rates (phi', theta', psi') from body rates: eq. (5), i.e. W^-1 Omega (singular at
// cos theta = 0, the zyx gimbal lock).
Eigen::Vector3d euler_rates_from_body_rates(double phi_rad, double theta_rad,
                                            const Eigen::Vector3d& body_rates_radps);
Eigen::Vector3d euler_rates_from_body_rates(const EulerTrig& attitude,
                                            const Eigen::Vector3d& body_rates_radps);

// p_q'' = ^I_B R (0, 0, a_q) + (0, 0, -g), eq. (4).
Eigen::Vector3d vehicle_acceleration_mps2(const VehicleState& state, double a_q_mps2,
                                          double gravity_mps2 = pa::kGravity_mps2);
Eigen::Vector3d vehicle_acceleration_mps2(const EulerTrig& attitude, double a_q_mps2,
                                          double gravity_mps2 = pa::kGravity_mps2);

// s_q' = f_q(s_q, u_q), eq. (8): (4) and (5).
VehicleState vehicle_dynamics(const VehicleState& state, const VehicleInput& input,
                              double gravity_mps2 = pa::kGravity_mps2);

}  // namespace gs::model
