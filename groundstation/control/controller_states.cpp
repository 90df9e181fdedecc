#include "groundstation/control/controller_states.hpp"

#include <algorithm>
#include <cmath>

#include "groundstation/control/balancing_lqr.hpp"
#include "groundstation/control/hover_lqr.hpp"

namespace gs::control {

Eigen::VectorXd hover_state(const model::VehicleState& vehicle, const Eigen::Vector3d& set_point_m) {
  Eigen::VectorXd x(hover::kStateSize);
  x.segment<3>(hover::kX) = vehicle.p_m - set_point_m;
  x.segment<3>(hover::kVx) = vehicle.v_mps;
  x(hover::kRoll) = vehicle.phi_rad;
  x(hover::kPitch) = vehicle.theta_rad;
  x(hover::kYaw) = vehicle.psi_rad;
  return x;
}

Eigen::VectorXd balancing_state(const Pivot& pivot, const model::VehicleState& vehicle,
                                const model::PoleState& pole, double half_length_m,
                                const Eigen::Vector3d& set_point_m) {
  namespace bal = balancing;
  Eigen::VectorXd x(bal::kStateSize);
  // From the centre relative to the pivot rather than from n, whose sign is the motion capture's
  // (either end may rest on the plate).
  const Eigen::Vector3d r = half_length_m * (pole.p_m - pivot.p_m).normalized();
  const Eigen::Vector3d r_dot = pole.v_mps - pivot.v_mps;
  x.segment<3>(bal::kX) = pivot.p_m - set_point_m;
  x.segment<3>(bal::kVx) = pivot.v_mps;
  x(bal::kRoll) = vehicle.phi_rad;
  x(bal::kPitch) = vehicle.theta_rad;
  x(bal::kYaw) = vehicle.psi_rad;
  x(bal::kA) = r.x();
  x(bal::kB) = r.y();
  x(bal::kADot) = r_dot.x();
  x(bal::kBDot) = r_dot.y();
  return x;
}

model::PlanarState<double> planar_throw_state(const Pivot& pivot, const model::VehicleState& vehicle,
                                              const model::PoleState& pole, const Eigen::Vector3d& origin_m) {
  namespace planar = model::planar;
  // The thrust axis ^I_B R e_z; its pitch in the x-z plane is the planar theta.
  const Eigen::Vector3d thrust_axis =
      model::rotation_inertial_from_body(vehicle.phi_rad, vehicle.theta_rad, vehicle.psi_rad).col(2);
  model::PlanarState<double> s;
  s(planar::kX) = pivot.p_m.x() - origin_m.x();
  s(planar::kZ) = pivot.p_m.z() - origin_m.z();
  s(planar::kVx) = pivot.v_mps.x();
  s(planar::kVz) = pivot.v_mps.z();
  s(planar::kTheta) = std::atan2(thrust_axis.x(), thrust_axis.z());
  // alpha from the centre relative to the pivot (n's sign is the motion capture's), and its rate
  // from the relative velocity: alpha' = (r_z r_x' - r_x r_z') / (r_x^2 + r_z^2).
  const Eigen::Vector3d r = pole.p_m - pivot.p_m;
  const Eigen::Vector3d r_dot = pole.v_mps - pivot.v_mps;
  const double rr = std::max(r.x() * r.x() + r.z() * r.z(), 1e-9);
  s(planar::kAlpha) = std::atan2(r.x(), r.z());
  s(planar::kAlphaDot) = (r.z() * r_dot.x() - r.x() * r_dot.z()) / rr;
  return s;
}

}  // namespace gs::control
