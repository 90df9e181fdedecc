#include "groundstation/estimation/vehicle_observer.hpp"

#include <algorithm>
#include <cmath>

namespace gs::estimation {
namespace {

bool finite_input(const model::VehicleInput& in) {
  return std::isfinite(in.a_q_mps2) && in.omega_radps.allFinite();
}

}  // namespace

VehicleObserver::VehicleObserver(const VehicleObserverParams& params) : params_(params) {
  for (int i = 0; i < 3; ++i) {
    trans_x_[i].setZero();
    trans_p_[i].setIdentity();
    att_x_[i].setZero();
    att_p_[i].setIdentity();
  }
}

void VehicleObserver::reset(const MocapPose& pose) {
  if (!is_usable_pose(pose)) return;
  plate_.reset();
  const EulerZyx e = euler_zyx_from_quaternion(pose.q);
  const double eta[3] = {e.phi_rad, e.theta_rad, e.psi_rad};
  const double sp = params_.mocap_position_sigma_m;
  const double sa = params_.mocap_attitude_sigma_rad;
  const double sv = params_.initial_velocity_sigma_mps;
  const double sd = params_.initial_disturbance_sigma_mps2;
  const double sr = params_.initial_rate_sigma_radps;
  for (int i = 0; i < 3; ++i) {
    trans_x_[i] = Eigen::Vector3d(pose.p_m(i), 0.0, 0.0);
    trans_p_[i] = Eigen::Vector3d(sp * sp, sv * sv, sd * sd).asDiagonal();
    att_x_[i] = Eigen::Vector2d(eta[i], 0.0);
    att_p_[i] = Eigen::Vector2d(sa * sa, sr * sr).asDiagonal();
  }
  // Until a command says otherwise there is no input: d holds the whole acceleration (zero at
  // rest), and the first command re-expresses it (see predict).
  commanded_ = false;
  thrust_mps2_ = params_.gravity_mps2;
  rates_radps_.setZero();
  rate_derivative_radps2_.setZero();
  rejections_ = 0;
  initialised_ = true;
}

model::EulerTrig VehicleObserver::attitude() const { return {att_x_[0](0), att_x_[1](0), att_x_[2](0)}; }

void VehicleObserver::predict(double dt_s, const model::VehicleInput* command, Propagation propagation) {
  if (!initialised_ || !(dt_s > 0.0) || !std::isfinite(dt_s)) return;
  plate_.reset();
  const bool commanded = command != nullptr && finite_input(*command);

  // The acceleration and Euler rate the filter currently believes in, kept continuous when the
  // input model changes (d and delta take up the difference): only then is it evaluated.
  const model::EulerTrig eta = attitude();
  std::optional<VehicleEstimate> before;
  if (commanded != commanded_) before = estimate(eta);
  if (commanded && !commanded_) {
    thrust_mps2_ = (before->acceleration_mps2 + Eigen::Vector3d(0.0, 0.0, params_.gravity_mps2)).norm();
    rates_radps_ = before->body_rates_radps;
    rate_derivative_radps2_.setZero();
  }

  Eigen::Vector3d u = Eigen::Vector3d::Zero();
  Eigen::Vector3d r = Eigen::Vector3d::Zero();
  if (commanded) {
    // The thrust's first-order lag solved exactly over the step, the rates' second-order response
    // integrated; the inputs use their means over the step.
    const auto lag = [dt_s](double tau, double& decay, double& mean_weight) {
      decay = tau > 0.0 ? std::exp(-dt_s / tau) : 0.0;
      mean_weight = tau > 0.0 ? tau / dt_s * (1.0 - decay) : 0.0;
    };
    double decay = 0.0;
    double mean_weight = 0.0;
    lag(params_.thrust_time_constant_s, decay, mean_weight);
    const double a_c = command->a_q_mps2;
    // u = ^I_B R(eta) e_z a_q - g e_z, eq. (4).
    u = model::vehicle_acceleration_mps2(eta, a_c + (thrust_mps2_ - a_c) * mean_weight, params_.gravity_mps2);
    thrust_mps2_ = a_c + (thrust_mps2_ - a_c) * decay;
    const Eigen::Vector3d w_mean = propagate_rates(dt_s, command->omega_radps);
    r = model::euler_rates_from_body_rates(eta, w_mean);  // (5)
  }
  if (before) {
    for (int i = 0; i < 3; ++i) {
      trans_x_[i](2) = before->acceleration_mps2(i) - u(i);
      att_x_[i](1) = before->euler_rates_radps(i) - r(i);
    }
    commanded_ = commanded;
  }

  const double h = dt_s;
  if (propagation == Propagation::mean_only) {
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector3d& x = trans_x_[i];
      trans_x_[i] =
          Eigen::Vector3d(x(0) + h * x(1) + 0.5 * h * h * (x(2) + u(i)), x(1) + h * (x(2) + u(i)), x(2));
      att_x_[i](0) += h * (att_x_[i](1) + r(i));
    }
    return;
  }
  const VehicleProcessNoise& q = commanded ? params_.commanded : params_.uncommanded;
  const double h2 = h * h;
  const double h3 = h2 * h;
  Eigen::Matrix3d phi;
  phi << 1.0, h, 0.5 * h2, 0.0, 1.0, h, 0.0, 0.0, 1.0;
  Eigen::Matrix3d q_trans;
  q_trans << h3 / 3.0, h2 / 2.0, 0.0, h2 / 2.0, h, 0.0, 0.0, 0.0, 0.0;
  q_trans *= q.acceleration_psd;
  Eigen::Matrix3d q_jerk;
  q_jerk << h2 * h3 / 20.0, h2 * h2 / 8.0, h3 / 6.0, h2 * h2 / 8.0, h3 / 3.0, h2 / 2.0, h3 / 6.0, h2 / 2.0, h;
  q_trans += q.disturbance_jerk_psd * q_jerk;
  Eigen::Matrix2d phi_att;
  phi_att << 1.0, h, 0.0, 1.0;
  Eigen::Matrix2d q_att;
  q_att << q.euler_rate_psd * h + q.rate_correction_psd * h3 / 3.0, q.rate_correction_psd * h2 / 2.0,
      q.rate_correction_psd * h2 / 2.0, q.rate_correction_psd * h;

  for (int i = 0; i < 3; ++i) {
    trans_x_[i] = phi * trans_x_[i] + Eigen::Vector3d(0.5 * h2, h, 0.0) * u(i);
    trans_p_[i] = phi * trans_p_[i] * phi.transpose() + q_trans;
    att_x_[i] = phi_att * att_x_[i] + Eigen::Vector2d(h, 0.0) * r(i);
    att_p_[i] = phi_att * att_p_[i] * phi_att.transpose() + q_att;
  }
}

// The rate loop's second-order response (see the header) to a command held over dt_s: RK4 in
// steps of at most 1 ms (omega_n h <= 0.04, far inside RK4's accuracy), returning the mean rate
// over dt_s for the attitude's propagation.
Eigen::Vector3d VehicleObserver::propagate_rates(double dt_s, const Eigen::Vector3d& command_radps) {
  const Eigen::Vector3d w2 = params_.rate_natural_frequency_radps.cwiseAbs2();
  const Eigen::Vector3d two_zeta_w =
      2.0 * params_.rate_damping.cwiseProduct(params_.rate_natural_frequency_radps);
  const auto accel = [&](const Eigen::Vector3d& w, const Eigen::Vector3d& wd) -> Eigen::Vector3d {
    return w2.cwiseProduct(command_radps - w) - two_zeta_w.cwiseProduct(wd);
  };
  const int n = std::max(1, static_cast<int>(std::ceil(dt_s / 0.001)));
  const double h = dt_s / n;
  Eigen::Vector3d w = rates_radps_;
  Eigen::Vector3d wd = rate_derivative_radps2_;
  Eigen::Vector3d integral = Eigen::Vector3d::Zero();
  for (int k = 0; k < n; ++k) {
    // RK4 on (integral, w, w'): integral' = w, w' = wd, wd' = accel(w, wd).
    const Eigen::Vector3d k1w = wd, k1d = accel(w, wd);
    const Eigen::Vector3d k2w = wd + 0.5 * h * k1d, k2d = accel(w + 0.5 * h * k1w, wd + 0.5 * h * k1d);
    const Eigen::Vector3d k3w = wd + 0.5 * h * k2d, k3d = accel(w + 0.5 * h * k2w, wd + 0.5 * h * k2d);
    const Eigen::Vector3d k4w = wd + h * k3d, k4d = accel(w + h * k3w, wd + h * k3d);
    integral += h / 6.0 * (w + 2.0 * (w + 0.5 * h * k1w) + 2.0 * (w + 0.5 * h * k2w) + (w + h * k3w));
    w += h / 6.0 * (k1w + 2.0 * k2w + 2.0 * k3w + k4w);
    wd += h / 6.0 * (k1d + 2.0 * k2d + 2.0 * k3d + k4d);
  }
  rates_radps_ = w;
  rate_derivative_radps2_ = wd;
  return integral / dt_s;
}

double VehicleObserver::nis(const MocapPose& pose) const {
  if (!initialised_ || !is_usable_pose(pose)) return 0.0;
  const EulerZyx e = euler_zyx_from_quaternion(pose.q);
  const double eta[3] = {e.phi_rad, e.theta_rad, e.psi_rad};
  const double rp = params_.mocap_position_sigma_m * params_.mocap_position_sigma_m;
  const double ra = params_.mocap_attitude_sigma_rad * params_.mocap_attitude_sigma_rad;
  double nis = 0.0;
  for (int i = 0; i < 3; ++i) {
    const double nu_p = pose.p_m(i) - trans_x_[i](0);
    const double nu_a = wrap_angle_rad(eta[i] - att_x_[i](0));
    nis += nu_p * nu_p / (trans_p_[i](0, 0) + rp) + nu_a * nu_a / (att_p_[i](0, 0) + ra);
  }
  return nis;
}

VehicleUpdateResult VehicleObserver::update(const MocapPose& pose) {
  VehicleUpdateResult result;
  if (!is_usable_pose(pose)) return result;
  if (!initialised_) {
    reset(pose);
    result.accepted = true;
    result.reinitialised = true;
    return result;
  }
  result.nis = nis(pose);
  if (result.nis > params_.outlier_nis) {
    if (++rejections_ > params_.max_rejections) {
      reset(pose);
      result.accepted = true;
      result.reinitialised = true;
    }
    return result;
  }
  rejections_ = 0;
  plate_.reset();
  const EulerZyx e = euler_zyx_from_quaternion(pose.q);
  const double eta[3] = {e.phi_rad, e.theta_rad, e.psi_rad};
  const double rp = params_.mocap_position_sigma_m * params_.mocap_position_sigma_m;
  const double ra = params_.mocap_attitude_sigma_rad * params_.mocap_attitude_sigma_rad;
  for (int i = 0; i < 3; ++i) {
    {
      const double s = trans_p_[i](0, 0) + rp;
      const Eigen::Vector3d k = trans_p_[i].col(0) / s;
      trans_x_[i] += k * (pose.p_m(i) - trans_x_[i](0));
      trans_p_[i] -= k * trans_p_[i].row(0);
      trans_p_[i] = 0.5 * (trans_p_[i] + trans_p_[i].transpose()).eval();
    }
    {
      const double s = att_p_[i](0, 0) + ra;
      const Eigen::Vector2d k = att_p_[i].col(0) / s;
      att_x_[i] += k * wrap_angle_rad(eta[i] - att_x_[i](0));
      att_p_[i] -= k * att_p_[i].row(0);
      att_p_[i] = 0.5 * (att_p_[i] + att_p_[i].transpose()).eval();
    }
  }
  // Keep yaw in (-pi, pi] (roll likewise); the innovation above is already wrapped.
  att_x_[0](0) = wrap_angle_rad(att_x_[0](0));
  att_x_[2](0) = wrap_angle_rad(att_x_[2](0));
  result.accepted = true;
  return result;
}

VehicleEstimate VehicleObserver::estimate() const { return estimate(attitude()); }

VehicleEstimate VehicleObserver::estimate(const model::EulerTrig& eta) const {
  VehicleEstimate e;
  e.state.phi_rad = eta.phi_rad;
  e.state.theta_rad = eta.theta_rad;
  e.state.psi_rad = eta.psi_rad;
  Eigen::Vector3d d;
  Eigen::Vector3d delta;
  for (int i = 0; i < 3; ++i) {
    e.state.p_m(i) = trans_x_[i](0);
    e.state.v_mps(i) = trans_x_[i](1);
    d(i) = trans_x_[i](2);
    delta(i) = att_x_[i](1);
    e.position_sigma_m(i) = std::sqrt(trans_p_[i](0, 0));
    e.velocity_sigma_mps(i) = std::sqrt(trans_p_[i](1, 1));
    e.acceleration_sigma_mps2(i) = std::sqrt(trans_p_[i](2, 2));
    e.attitude_sigma_rad(i) = std::sqrt(att_p_[i](0, 0));
  }
  e.acceleration_mps2 = d;
  e.euler_rates_radps = delta;
  if (commanded_) {
    // The inputs re-evaluated at the current attitude and applied thrust.
    e.acceleration_mps2 += model::vehicle_acceleration_mps2(eta, thrust_mps2_, params_.gravity_mps2);
    e.euler_rates_radps += model::euler_rates_from_body_rates(eta, rates_radps_);
    e.body_rate_derivative_radps2 = rate_derivative_radps2_;
  }
  e.body_rates_radps = model::body_rates_from_euler_rates(eta, e.euler_rates_radps);
  return e;
}

const PlateKinematics& VehicleObserver::plate() const {
  if (!plate_) plate_ = plate_now();
  return *plate_;
}

PlateKinematics VehicleObserver::plate_now() const {
  const model::EulerTrig eta = attitude();
  const VehicleEstimate e = estimate(eta);
  PlateKinematics k;
  k.inertial_from_body = model::rotation_inertial_from_body(eta);
  const Eigen::Vector3d r_h = params_.plate_height_m * k.inertial_from_body.col(2);
  const Eigen::Vector3d omega_inertial = k.inertial_from_body * e.body_rates_radps;
  k.p_m = e.state.p_m + r_h;
  k.v_mps = e.state.v_mps + omega_inertial.cross(r_h);
  // d(R Omega)/dt = R Omega' (the R [Omega]x Omega term vanishes).
  const Eigen::Vector3d omega_dot_inertial = k.inertial_from_body * e.body_rate_derivative_radps2;
  k.a_mps2 =
      e.acceleration_mps2 + omega_dot_inertial.cross(r_h) + omega_inertial.cross(omega_inertial.cross(r_h));
  k.position_variance_m2 = e.position_sigma_m.squaredNorm() / 3.0 +
                           std::pow(params_.plate_height_m * e.attitude_sigma_rad.head<2>().norm(), 2);
  k.velocity_variance_m2ps2 = e.velocity_sigma_mps.squaredNorm() / 3.0;
  k.acceleration_variance_m2ps4 = e.acceleration_sigma_mps2.squaredNorm() / 3.0;
  return k;
}

}  // namespace gs::estimation
