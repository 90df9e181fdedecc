#include "groundstation/estimation/pole_mode_conversion.hpp"

#include <cmath>

#include "groundstation/model/impact.hpp"

namespace gs::estimation {
namespace {

using Vector12 = Eigen::Matrix<double, 12, 1>;
using Vector6 = PoleOnVehicleEkf::StateVector;
using Jacobian6x12 = Eigen::Matrix<double, 6, 12>;

Vector12 flatten(const model::PoleState& s) {
  Vector12 v;
  v << s.p_m, s.v_mps, s.n, s.omega_radps;
  return v;
}

model::PoleState unflatten(const Vector12& v) {
  model::PoleState s;
  s.p_m = v.segment<3>(0);
  s.v_mps = v.segment<3>(3);
  s.n = v.segment<3>(6);
  s.omega_radps = v.segment<3>(9);
  return s;
}

// The on-vehicle coordinates (24) of a pole whose end at -L n_pivot rests on the plate, with
// n_pivot = sign * n.
Vector6 on_vehicle_coordinates(const model::PoleState& pole, double sign, const PlateKinematics& plate,
                               const model::PoleParams& params) {
  const Eigen::Vector3d r = params.half_length_m * sign * pole.n;
  const Eigen::Vector3d r_dot = pole.omega_radps.cross(r);
  const Eigen::Vector3d rel = plate.inertial_from_body.transpose() * (pole.p_m - r - plate.p_m);
  Vector6 x;
  x << r.x(), r.y(), r_dot.x(), r_dot.y(), rel.x(), rel.y();
  return x;
}

// Forward-difference Jacobian of a map from the 12 pole coordinates.
template <typename F>
Jacobian6x12 jacobian_of(F&& f, const model::PoleState& at) {
  const Vector12 x0 = flatten(at);
  const Vector6 y0 = f(at);
  Jacobian6x12 j;
  for (int c = 0; c < 12; ++c) {
    Vector12 x = x0;
    const double eps = 1e-7 * std::max(1.0, std::abs(x0(c)));
    x(c) += eps;
    j.col(c) = (f(unflatten(x)) - y0) / eps;
  }
  return j;
}

void add_plate_uncertainty(PoleOnVehicleEkf::StateCovariance& p, const PlateKinematics& plate) {
  p(PoleOnVehicleEkf::kOx, PoleOnVehicleEkf::kOx) += plate.position_variance_m2;
  p(PoleOnVehicleEkf::kOy, PoleOnVehicleEkf::kOy) += plate.position_variance_m2;
}

}  // namespace

PlateContactGeometry plate_contact_geometry(const model::PoleState& pole, const PlateKinematics& plate,
                                            const model::PoleParams& params) {
  const double sign = pole.n.z() >= 0.0 ? 1.0 : -1.0;  // the lower end is p - L sign n
  const Eigen::Vector3d arm = -params.half_length_m * sign * pole.n;
  PlateContactGeometry g;
  g.end_m = pole.p_m + arm;
  const Eigen::Vector3d rel = plate.inertial_from_body.transpose() * (g.end_m - plate.p_m);
  g.height_m = rel.z();
  g.radial_m = rel.head<2>().norm();
  const Eigen::Vector3d end_velocity = pole.v_mps + pole.omega_radps.cross(arm);
  g.approach_speed_mps = -(end_velocity - plate.v_mps).dot(plate.normal());
  return g;
}

std::optional<OnVehicleSeed> on_vehicle_seed_from_free_flight(const model::PoleState& pole,
                                                              const PoleCovariance& covariance,
                                                              const PlateKinematics& plate,
                                                              const model::PoleParams& params,
                                                              const PlateContactGate& gate) {
  const double sign = pole.n.z() >= 0.0 ? 1.0 : -1.0;
  if (sign * pole.n.z() < std::cos(gate.max_tilt_rad)) return std::nullopt;
  const PlateContactGeometry g = plate_contact_geometry(pole, plate, params);
  if (g.radial_m > gate.plate_radius_m + gate.radial_margin_m ||
      std::abs(g.height_m) > gate.height_margin_m) {
    return std::nullopt;
  }
  const auto f = [&](const model::PoleState& s) { return on_vehicle_coordinates(s, sign, plate, params); };
  OnVehicleSeed seed;
  seed.direction_sign = sign;
  seed.state = f(pole);
  const Jacobian6x12 j = jacobian_of(f, pole);
  seed.covariance = congruence(j, covariance);
  add_plate_uncertainty(seed.covariance, plate);
  return seed;
}

OnVehicleSeed on_vehicle_seed_after_impact(const model::PoleState& before, const PoleCovariance& covariance,
                                           const PlateKinematics& plate, const model::PoleParams& params,
                                           double impact_rate_sigma_mps) {
  const double sign = before.n.z() >= 0.0 ? 1.0 : -1.0;
  const auto f = [&](const model::PoleState& s) {
    const model::ImpactResult r = model::impact_map(s, plate.v_mps, params);  // (35)-(40)
    const Eigen::Vector3d rel = plate.inertial_from_body.transpose() * (r.contact_point_m - plate.p_m);
    Vector6 x;
    x << r.on_vehicle.a_m, r.on_vehicle.b_m, r.on_vehicle.a_dot_mps, r.on_vehicle.b_dot_mps, rel.x(), rel.y();
    return x;
  };
  OnVehicleSeed seed;
  seed.direction_sign = sign;
  seed.state = f(before);
  const Jacobian6x12 j = jacobian_of(f, before);
  seed.covariance = congruence(j, covariance);
  add_plate_uncertainty(seed.covariance, plate);
  // The plate's velocity enters (38), (39) as 3/4 of a rate of L n; and the impact model itself.
  const double rate_var =
      impact_rate_sigma_mps * impact_rate_sigma_mps + 0.5625 * plate.velocity_variance_m2ps2;
  seed.covariance(PoleOnVehicleEkf::kAdot, PoleOnVehicleEkf::kAdot) += rate_var;
  seed.covariance(PoleOnVehicleEkf::kBdot, PoleOnVehicleEkf::kBdot) += rate_var;
  return seed;
}

FreeFlightSeed free_flight_seed_from_on_vehicle(const PoleOnVehicleEkf& ekf, const PlateKinematics& plate) {
  FreeFlightSeed seed;
  seed.state = ekf.free_flight_state(plate);
  const Eigen::Matrix<double, 12, PoleOnVehicleEkf::kSize> j = ekf.free_flight_jacobian(plate);
  seed.covariance = congruence(j, ekf.covariance());
  seed.covariance.block<3, 3>(0, 0) += plate.position_variance_m2 * Eigen::Matrix3d::Identity();
  seed.covariance.block<3, 3>(3, 3) += plate.velocity_variance_m2ps2 * Eigen::Matrix3d::Identity();
  return seed;
}

}  // namespace gs::estimation
