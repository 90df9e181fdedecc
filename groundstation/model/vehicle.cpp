#include "groundstation/model/vehicle.hpp"

#include <cmath>

namespace gs::model {

VehicleState operator+(const VehicleState& lhs, const VehicleState& rhs) {
  return {lhs.p_m + rhs.p_m, lhs.v_mps + rhs.v_mps, lhs.phi_rad + rhs.phi_rad, lhs.theta_rad + rhs.theta_rad,
          lhs.psi_rad + rhs.psi_rad};
}

VehicleState operator*(double scale, const VehicleState& state) {
  return {scale * state.p_m, scale * state.v_mps, scale * state.phi_rad, scale * state.theta_rad,
          scale * state.psi_rad};
}

// Passive rotations: the coordinates of a fixed vector in a frame turned by +angle about the axis.
namespace {

Eigen::Matrix3d rotation_x(double c, double s) {
  Eigen::Matrix3d r;
  r << 1.0, 0.0, 0.0, 0.0, c, s, 0.0, -s, c;
  return r;
}

Eigen::Matrix3d rotation_y(double c, double s) {
  Eigen::Matrix3d r;
  r << c, 0.0, -s, 0.0, 1.0, 0.0, s, 0.0, c;
  return r;
}

Eigen::Matrix3d rotation_z(double c, double s) {
  Eigen::Matrix3d r;
  r << c, s, 0.0, -s, c, 0.0, 0.0, 0.0, 1.0;
  return r;
}

}  // namespace

EulerTrig::EulerTrig(double phi, double theta, double psi)
    : phi_rad(phi),
      theta_rad(theta),
      psi_rad(psi),
      sin_phi(std::sin(phi)),
      cos_phi(std::cos(phi)),
      sin_theta(std::sin(theta)),
      cos_theta(std::cos(theta)),
      sin_psi(std::sin(psi)),
      cos_psi(std::cos(psi)) {}

Eigen::Matrix3d rotation_x(double angle_rad) { return rotation_x(std::cos(angle_rad), std::sin(angle_rad)); }
Eigen::Matrix3d rotation_y(double angle_rad) { return rotation_y(std::cos(angle_rad), std::sin(angle_rad)); }
Eigen::Matrix3d rotation_z(double angle_rad) { return rotation_z(std::cos(angle_rad), std::sin(angle_rad)); }

Eigen::Matrix3d rotation_body_from_inertial(const EulerTrig& a) {
  return rotation_x(a.cos_phi, a.sin_phi) * rotation_y(a.cos_theta, a.sin_theta) *
         rotation_z(a.cos_psi, a.sin_psi);  // eq. (3)
}

Eigen::Matrix3d rotation_body_from_inertial(double phi_rad, double theta_rad, double psi_rad) {
  return rotation_body_from_inertial(EulerTrig(phi_rad, theta_rad, psi_rad));
}

Eigen::Matrix3d rotation_inertial_from_body(const EulerTrig& a) {
  return rotation_body_from_inertial(a).transpose();
}

Eigen::Matrix3d rotation_inertial_from_body(double phi_rad, double theta_rad, double psi_rad) {
  return rotation_body_from_inertial(phi_rad, theta_rad, psi_rad).transpose();
}

namespace {

// The rate maps of (5) depend on roll and pitch alone: from their sines and cosines, so that the
// angle overloads evaluate no yaw.
// The columns of W are the body-frame images of the three Euler axes: e_x for phi',
// R_x(phi) e_y for theta', R_x(phi) R_y(theta) e_z for psi'. That is the printed matrix of (5).
Eigen::Vector3d body_rates_from_trig(double sp, double cp, double st, double ct,
                                     const Eigen::Vector3d& euler_rates_radps) {
  Eigen::Matrix3d w;
  w << 1.0, 0.0, -st, 0.0, cp, sp * ct, 0.0, -sp, cp * ct;
  return w * euler_rates_radps;
}

// Eq. (5) is the inverse of the printed matrix applied to Omega (docs/paper-notes.md); written out:
//   phi'   = Omega_x + tan(theta) (sin(phi) Omega_y + cos(phi) Omega_z)
//   theta' = cos(phi) Omega_y - sin(phi) Omega_z
//   psi'   = (sin(phi) Omega_y + cos(phi) Omega_z) / cos(theta)
Eigen::Vector3d euler_rates_from_trig(double sp, double cp, double ct, double theta_rad,
                                      const Eigen::Vector3d& body_rates_radps) {
  const double yz = sp * body_rates_radps.y() + cp * body_rates_radps.z();
  return {body_rates_radps.x() + std::tan(theta_rad) * yz,
          cp * body_rates_radps.y() - sp * body_rates_radps.z(), yz / ct};
}

}  // namespace

Eigen::Vector3d body_rates_from_euler_rates(const EulerTrig& a, const Eigen::Vector3d& euler_rates_radps) {
  return body_rates_from_trig(a.sin_phi, a.cos_phi, a.sin_theta, a.cos_theta, euler_rates_radps);
}

Eigen::Vector3d body_rates_from_euler_rates(double phi_rad, double theta_rad,
                                            const Eigen::Vector3d& euler_rates_radps) {
  return body_rates_from_trig(std::sin(phi_rad), std::cos(phi_rad), std::sin(theta_rad), std::cos(theta_rad),
                              euler_rates_radps);
}

Eigen::Vector3d euler_rates_from_body_rates(const EulerTrig& a, const Eigen::Vector3d& body_rates_radps) {
  return euler_rates_from_trig(a.sin_phi, a.cos_phi, a.cos_theta, a.theta_rad, body_rates_radps);
}

Eigen::Vector3d euler_rates_from_body_rates(double phi_rad, double theta_rad,
                                            const Eigen::Vector3d& body_rates_radps) {
  return euler_rates_from_trig(std::sin(phi_rad), std::cos(phi_rad), std::cos(theta_rad), theta_rad,
                               body_rates_radps);
}

// ^I_B R e_z is the third row of ^B_I R = R_x R_y R_z.
Eigen::Vector3d vehicle_acceleration_mps2(const EulerTrig& a, double a_q_mps2, double gravity_mps2) {
  const Eigen::Vector3d thrust_direction = rotation_body_from_inertial(a).row(2).transpose();
  return a_q_mps2 * thrust_direction - Eigen::Vector3d(0.0, 0.0, gravity_mps2);
}

Eigen::Vector3d vehicle_acceleration_mps2(const VehicleState& state, double a_q_mps2, double gravity_mps2) {
  return vehicle_acceleration_mps2(EulerTrig(state.phi_rad, state.theta_rad, state.psi_rad), a_q_mps2,
                                   gravity_mps2);
}

VehicleState vehicle_dynamics(const VehicleState& state, const VehicleInput& input, double gravity_mps2) {
  const Eigen::Vector3d euler_rates =
      euler_rates_from_body_rates(state.phi_rad, state.theta_rad, input.omega_radps);
  return {state.v_mps, vehicle_acceleration_mps2(state, input.a_q_mps2, gravity_mps2), euler_rates.x(),
          euler_rates.y(), euler_rates.z()};
}

}  // namespace gs::model
