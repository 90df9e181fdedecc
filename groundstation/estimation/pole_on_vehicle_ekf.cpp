#include "groundstation/estimation/pole_on_vehicle_ekf.hpp"

#include <algorithm>
#include <cmath>

#include "groundstation/estimation/mocap_pose.hpp"
#include "groundstation/model/rk4.hpp"

namespace gs::estimation {

double pole_normal_force_per_mass_mps2(const model::PoleOnVehicleState& pole,
                                       const Eigen::Vector3d& specific_force_mps2,
                                       const Eigen::Vector3d& plate_normal, const model::PoleParams& params) {
  const double length = params.half_length_m;
  const Eigen::Vector3d r = length * model::pole_direction_on_vehicle(pole, params);
  const Eigen::Vector3d r_dot = model::pole_centre_velocity_relative_to_pivot_mps(pole, params);
  const double mu = (0.75 * specific_force_mps2.dot(r) - r_dot.squaredNorm()) / (length * length);
  return (0.25 * specific_force_mps2 + mu * r).dot(plate_normal);
}

namespace {
// 0 up to `low`, 1 from `high`, linear between; 0 for NaN.
double ramp(double x, double low, double high) {
  if (!(x > low)) return 0.0;
  return x >= high ? 1.0 : (x - low) / (high - low);
}
}  // namespace

double pole_measurement_sigma(double motor_lag_s, double mocap_noise, const PoleTrust& trust) {
  const double f = std::max(ramp(motor_lag_s, trust.fast_lag_s, trust.slow_lag_s),
                            ramp(mocap_noise, trust.quiet_noise, trust.noisy_noise));
  return trust.trusting_sigma + f * (trust.wary_sigma - trust.trusting_sigma);
}

PoleOnVehicleEkf::PoleOnVehicleEkf(const PoleOnVehicleEkfParams& params)
    : params_(params),
      gain_position_sigma_m_(params.mocap_position_sigma_m),
      gain_direction_sigma_rad_(params.mocap_direction_sigma_rad) {}

void PoleOnVehicleEkf::reset(const StateVector& state, const StateCovariance& covariance,
                             double direction_sign) {
  x_ = state;
  p_ = 0.5 * (covariance + covariance.transpose());
  sign_ = direction_sign >= 0.0 ? 1.0 : -1.0;
  last_nis_ = 0.0;
  valid_ = x_.allFinite() && p_.allFinite();
  if (valid_) valid_ = check_valid();
}

bool PoleOnVehicleEkf::check_valid() {
  const double rmax = params_.pole.half_length_m * std::sin(params_.max_tilt_rad);
  const double r = std::hypot(x_(kA), x_(kB));
  if (r <= rmax) return true;
  x_.head<2>() *= rmax / r;  // keeps (24) defined for whoever still reads the state
  return false;
}

PoleOnVehicleEkf::StateCovariance PoleOnVehicleEkf::jacobian(
    const Eigen::Vector3d& pivot_acceleration_mps2) const {
  StateCovariance f = StateCovariance::Zero();
  f(kA, kAdot) = 1.0;
  f(kB, kBdot) = 1.0;
  const model::PoleOnVehicleState base = pole();
  const Eigen::Vector2d acc0 =
      model::pole_on_vehicle_acceleration_mps2(base, pivot_acceleration_mps2, params_.pole);
  for (int j = 0; j < 4; ++j) {
    model::PoleOnVehicleState s = base;
    double* field = j == 0 ? &s.a_m : j == 1 ? &s.b_m : j == 2 ? &s.a_dot_mps : &s.b_dot_mps;
    const double eps = 1e-7 * std::max(1.0, std::abs(*field));
    *field += eps;
    const Eigen::Vector2d acc =
        model::pole_on_vehicle_acceleration_mps2(s, pivot_acceleration_mps2, params_.pole);
    f.block<2, 1>(kAdot, j) = (acc - acc0) / eps;  // (28), (29)
  }
  return f;
}

void PoleOnVehicleEkf::step(double h, const Eigen::Vector3d& pivot_acceleration_mps2,
                            Propagation propagation) {
  if (propagation == Propagation::mean_and_covariance) {
    const StateCovariance f = jacobian(pivot_acceleration_mps2);
    StateCovariance m = StateCovariance::Zero();
    m(kAdot, kAdot) = params_.acceleration_psd;
    m(kBdot, kBdot) = params_.acceleration_psd;
    m(kOx, kOx) = params_.offset_psd;
    m(kOy, kOy) = params_.offset_psd;
    const StateCovariance fh = f * h;
    const StateCovariance phi = StateCovariance::Identity() + fh + 0.5 * fh * fh;
    const StateCovariance fm = f * m;
    const StateCovariance qd =
        m * h + 0.5 * h * h * (fm + fm.transpose()) + (h * h * h / 3.0) * fm * f.transpose();
    p_ = phi * p_ * phi.transpose() + qd;
    p_ = 0.5 * (p_ + p_.transpose()).eval();
  }

  const model::PoleOnVehicleState next = model::rk4_step(
      [&](const model::PoleOnVehicleState& s) {
        return model::pole_on_vehicle_derivative(s, pivot_acceleration_mps2, params_.pole);
      },
      pole(), h);
  x_(kA) = next.a_m;
  x_(kB) = next.b_m;
  x_(kAdot) = next.a_dot_mps;
  x_(kBdot) = next.b_dot_mps;
  if (!check_valid()) valid_ = false;
}

void PoleOnVehicleEkf::predict(double dt_s, const Eigen::Vector3d& pivot_acceleration_mps2,
                               Propagation propagation) {
  if (!valid_ || !(dt_s > 0.0) || !std::isfinite(dt_s) || !pivot_acceleration_mps2.allFinite()) {
    return;
  }
  const double max_step = params_.max_step_s > 0.0 ? params_.max_step_s : dt_s;
  const int steps = std::max(1, static_cast<int>(std::ceil(dt_s / max_step - 1e-9)));
  const double h = dt_s / steps;
  for (int i = 0; i < steps && valid_; ++i) step(h, pivot_acceleration_mps2, propagation);
}

Eigen::Vector3d PoleOnVehicleEkf::pivot_m(const PlateKinematics& plate) const {
  return plate.p_m + plate.inertial_from_body.col(0) * x_(kOx) + plate.inertial_from_body.col(1) * x_(kOy);
}

LinearisedPoleMeasurement<PoleOnVehicleEkf::kSize> PoleOnVehicleEkf::linearise(
    const PoleMeasurement& m, const PlateKinematics& plate) const {
  LinearisedPoleMeasurement<kSize> out;
  const double length = params_.pole.half_length_m;
  const model::PoleOnVehicleState s = pole();
  const Eigen::Vector3d n = model::pole_direction_on_vehicle(s, params_.pole);
  const double c = length * n.z();
  const Eigen::Matrix<double, 3, 2> b = tangent_basis(n);
  out.nu.head<3>() = m.p_m - (pivot_m(plate) + length * n);  // (23)
  out.nu.tail<2>() = b.transpose() * (sign_ * m.n);
  // d(L n)/da = (1, 0, -a/c), d(L n)/db = (0, 1, -b/c) from (24).
  Eigen::Matrix<double, 3, 2> dr;
  dr << 1.0, 0.0, 0.0, 1.0, -s.a_m / c, -s.b_m / c;
  out.h.block<3, 2>(0, kA) = dr;
  out.h.block<3, 2>(0, kOx) = plate.inertial_from_body.leftCols<2>();
  out.h.block<2, 2>(3, kA) = b.transpose() * dr / length;
  out.r =
      pole_measurement_noise(gain_position_sigma_m_, gain_direction_sigma_rad_, plate.position_variance_m2);
  return out;
}

PoleInnovation PoleOnVehicleEkf::innovation(const PoleMeasurement& measurement,
                                            const PlateKinematics& plate) const {
  if (!valid_) return {};
  // Judged on the motion capture's noise whatever the gain trusts (set_measurement_sigma).
  return pole_innovation(
      linearise(measurement, plate), p_,
      pole_measurement_noise(params_.mocap_position_sigma_m, params_.mocap_direction_sigma_rad,
                             plate.position_variance_m2));
}

PoleInnovation PoleOnVehicleEkf::update(const PoleMeasurement& measurement, const PlateKinematics& plate) {
  if (!valid_) return {};
  return update(measurement, plate, innovation(measurement, plate));
}

PoleInnovation PoleOnVehicleEkf::update(const PoleMeasurement& measurement, const PlateKinematics& plate,
                                        const PoleInnovation& inn) {
  if (!valid_) return {};
  if (!inn.valid) return inn;
  const LinearisedPoleMeasurement<kSize> m = linearise(measurement, plate);
  x_ += kalman_correction(m, inn, p_);
  if (!check_valid()) valid_ = false;
  last_nis_ = inn.nis;
  return inn;
}

model::PoleState PoleOnVehicleEkf::free_flight_state(const PlateKinematics& plate) const {
  model::PoleState s =
      model::free_flight_state_from_pole_on_vehicle(pole(), pivot_m(plate), plate.v_mps, params_.pole);
  s.n *= sign_;  // Omega is the same rigid-body rate whichever end n points to
  return s;
}

Eigen::Matrix<double, 12, PoleOnVehicleEkf::kSize> PoleOnVehicleEkf::free_flight_jacobian(
    const PlateKinematics& plate) const {
  const auto flat = [](const model::PoleState& s) {
    Eigen::Matrix<double, 12, 1> v;
    v << s.p_m, s.v_mps, s.n, s.omega_radps;
    return v;
  };
  Eigen::Matrix<double, 12, kSize> j;
  const Eigen::Matrix<double, 12, 1> base = flat(free_flight_state(plate));
  PoleOnVehicleEkf probe = *this;
  for (int c = 0; c < kSize; ++c) {
    const double eps = 1e-7;
    probe.x_ = x_;
    probe.x_(c) += eps;
    j.col(c) = (flat(probe.free_flight_state(plate)) - base) / eps;
  }
  return j;
}

NormalForceEstimate PoleOnVehicleEkf::normal_force(const PlateKinematics& plate) const {
  const Eigen::Vector3d f = plate.a_mps2 + Eigen::Vector3d(0.0, 0.0, params_.pole.gravity_mps2);
  const Eigen::Vector3d t = plate.normal();
  const model::PoleOnVehicleState s = pole();
  NormalForceEstimate out;
  out.value_mps2 = pole_normal_force_per_mass_mps2(s, f, t, params_.pole);
  // Variance: the state's (a, b, a', b') by forward differences, and the specific force's.
  Eigen::Matrix<double, 1, 4> j;
  for (int c = 0; c < 4; ++c) {
    model::PoleOnVehicleState q = s;
    double* field = c == 0 ? &q.a_m : c == 1 ? &q.b_m : c == 2 ? &q.a_dot_mps : &q.b_dot_mps;
    const double eps = 1e-7;
    *field += eps;
    j(c) = (pole_normal_force_per_mass_mps2(q, f, t, params_.pole) - out.value_mps2) / eps;
  }
  const double length = params_.pole.half_length_m;
  const Eigen::Vector3d r = length * model::pole_direction_on_vehicle(s, params_.pole);
  const Eigen::Vector3d grad_f = 0.25 * t + (0.75 * r.dot(t) / (length * length)) * r;
  const double var = (j * p_.topLeftCorner<4, 4>() * j.transpose())(0, 0) +
                     grad_f.squaredNorm() * plate.acceleration_variance_m2ps4;
  out.sigma_mps2 = std::sqrt(std::max(var, 0.0));
  return out;
}

}  // namespace gs::estimation
