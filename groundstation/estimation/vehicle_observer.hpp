// The quadrocopter state observer of Section IV: the vehicle is estimated separately from the
// pole (the pole does not act on it, Section II), from motion-capture poses, with the commanded
// inputs u_q = (a_q, Omega_q) (7) driving the model (4), (5).
//
// Structure. A Luenberger observer whose gains are those of a Kalman filter, computed online so
// that dropouts and irregular frame intervals are handled exactly. The model is split the way
// (4), (5) are: the translation is driven by the thrust along the estimated attitude, the
// attitude by the commanded rates, so per inertial axis i
//   p_i' = v_i,   v_i' = u_i + d_i,   d_i' = w          u = ^I_B R(eta) e_z a_q - g e_z   (4)
//   eta_i' = r_i + delta_i,   delta_i' = w'              r = W^-1(eta) Omega_q             (5)
// with d an acceleration disturbance (thrust scale, drag, the pole's reaction, wind) and delta an
// Euler-rate correction (the on-board rate loop's lag and bias), both random walks. The coupling
// of attitude errors into the acceleration is left to the process noise: per axis the filters are
// 3 and 2 states, so the observer costs well under a microsecond.
//
// Input lags. The collective thrust reaches the vehicle through the motors: a first-order lag
// (thrust_time_constant_s). The body rates reach it through the on-board rate loop, whose
// response is second order: the firmware commands an angular acceleration kp (Omega_q - Omega)
// and the motors deliver it through their lag tau_m, so tau_m Omega'' + Omega' = kp (Omega_q -
// Omega), a natural frequency sqrt(kp / tau_m) and a damping 1 / (2 sqrt(kp tau_m)) (the slow
// integral term left out). A first-order lag would make Omega' jump at every rate-command step,
// and with it the plate's acceleration and the pole's estimated normal force F_N: at the throw's
// release that called the launch too early and back again. The second-order model keeps Omega'
// continuous, as the vehicle's is. Omega' moves the catching plate (3 cm above the centre of
// gravity) by Omega' x r, several m/s^2 for the throw's pitch-rate steps: enough to matter for
// the pole's contact force at the launch. (The motor constants are documented choices, the paper
// leaves them open, docs/paper-notes.md.)
//
// Without commands (offline replay of a motion-capture log) u = 0 and r = 0: d becomes the whole
// acceleration and delta the whole Euler rate, with larger process noise (a kinematic
// constant-acceleration / constant-rate model).
//
// Units: SI. Time is passed in (predict(dt)).
#pragma once

#include <Eigen/Dense>
#include <array>
#include <optional>

#include "groundstation/estimation/mocap_pose.hpp"
#include "groundstation/estimation/propagation.hpp"
#include "groundstation/model/vehicle.hpp"
#include "pa/constants.hpp"

namespace gs::estimation {

// Process noise as power spectral densities of the driving white noises. With commands the
// model explains the motion (the residual is the lags' mismatch, thrust scale, drag); without
// them d and delta carry all of it. Tuned on the tests' truth world: at 1 mm / 1 mrad noise
// the estimate is then smoother than the measurement (vehicle_observer_test.cpp).
struct VehicleProcessNoise {
  double acceleration_psd = 0.005;    // on v', (m/s^2)^2 / Hz
  double disturbance_jerk_psd = 2.0;  // on d', (m/s^3)^2 / Hz
  double euler_rate_psd = 1e-4;       // on eta', (rad/s)^2 / Hz
  double rate_correction_psd = 5.0;   // on delta', (rad/s^2)^2 / Hz
};

struct VehicleObserverParams {
  double gravity_mps2 = pa::kGravity_mps2;
  double plate_height_m = pa::kPlateHeightAboveCg_m;  // catching plate above the CG (Sec. VII-A)
  double thrust_time_constant_s = 0.03;               // the airframe's motors (firmware config)
  // The rate loop's response per body axis (x, y, z), from the firmware's rate gains kp = 40, 40,
  // 12 /s and the 30 ms motor lag (see the header): omega_n = sqrt(kp / tau_m), zeta =
  // 1 / (2 sqrt(kp tau_m)).
  Eigen::Vector3d rate_natural_frequency_radps{36.5, 36.5, 20.0};
  Eigen::Vector3d rate_damping{0.46, 0.46, 0.83};
  // The poses' standard deviations: an arena's typical 1 mm / 1 mrad. The ground station flies
  // with more (GroundStationConfig::estimator).
  double mocap_position_sigma_m = 1e-3;
  double mocap_attitude_sigma_rad = 1e-3;
  VehicleProcessNoise commanded;  // a command drives the model
  VehicleProcessNoise uncommanded{0.005, 100.0, 1e-4, 1000.0};
  // Initial standard deviations of the unmeasured states.
  double initial_velocity_sigma_mps = 1.0;
  double initial_disturbance_sigma_mps2 = 3.0;
  double initial_rate_sigma_radps = 1.0;
  // A pose whose NIS (6 dof) exceeds this is rejected as a glitch; after max_rejections in a
  // row the observer re-initialises from the pose (the vehicle really is elsewhere).
  double outlier_nis = 60.0;
  int max_rejections = 5;
};

// The vehicle's estimated state (6) and what the pole estimators need of it.
struct VehicleEstimate {
  model::VehicleState state;
  Eigen::Vector3d acceleration_mps2 = Eigen::Vector3d::Zero();            // p_q'' estimate
  Eigen::Vector3d euler_rates_radps = Eigen::Vector3d::Zero();            // (phi', theta', psi')
  Eigen::Vector3d body_rates_radps = Eigen::Vector3d::Zero();             // Omega, eq. (5)
  Eigen::Vector3d body_rate_derivative_radps2 = Eigen::Vector3d::Zero();  // Omega' (rate loop)
  Eigen::Vector3d position_sigma_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_sigma_mps = Eigen::Vector3d::Zero();
  Eigen::Vector3d acceleration_sigma_mps2 = Eigen::Vector3d::Zero();
  Eigen::Vector3d attitude_sigma_rad = Eigen::Vector3d::Zero();  // (phi, theta, psi)
};

// The catching plate's centre (p_q + h ^I_B R e_z) and its motion: where the pole rests.
struct PlateKinematics {
  Eigen::Vector3d p_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_mps = Eigen::Vector3d::Zero();
  Eigen::Vector3d a_mps2 = Eigen::Vector3d::Zero();
  Eigen::Matrix3d inertial_from_body = Eigen::Matrix3d::Identity();  // its columns: plate axes
  double position_variance_m2 = 0.0;                                 // per axis, of the centre
  double velocity_variance_m2ps2 = 0.0;                              // per axis, of v_mps
  double acceleration_variance_m2ps4 = 0.0;                          // per axis, of a_mps2
  Eigen::Vector3d normal() const { return inertial_from_body.col(2); }
};

struct VehicleUpdateResult {
  bool accepted = false;
  bool reinitialised = false;
  double nis = 0.0;  // 6 dof: position and Euler angles
};

class VehicleObserver {
 public:
  explicit VehicleObserver(const VehicleObserverParams& params = {});

  // Starts from a pose, at rest, with the initial uncertainties of the params.
  void reset(const MocapPose& pose);
  bool initialised() const { return initialised_; }

  // Propagates by dt_s (>= 0). command: the input acting during the step; nullptr when unknown.
  void predict(double dt_s, const model::VehicleInput* command,
               Propagation propagation = Propagation::mean_and_covariance);

  // The NIS the pose would have, without updating.
  double nis(const MocapPose& pose) const;
  // Corrects with a pose (outliers are rejected, see the params). Unusable poses are ignored.
  VehicleUpdateResult update(const MocapPose& pose);

  VehicleEstimate estimate() const;
  // Kept until the next predict, update or reset: the estimator reads a plate some 25 times a
  // motion-capture frame (steps, contact gates, latency compensation), and each costs the
  // attitude's three sines and cosines and the estimate.
  const PlateKinematics& plate() const;
  const VehicleObserverParams& params() const { return params_; }

  // The per-axis filters, exposed for tests: (p, v, d) and (eta, delta) with covariances.
  const Eigen::Vector3d& translation(int axis) const { return trans_x_[axis]; }
  const Eigen::Matrix3d& translation_covariance(int axis) const { return trans_p_[axis]; }
  const Eigen::Vector2d& attitude(int axis) const { return att_x_[axis]; }
  const Eigen::Matrix2d& attitude_covariance(int axis) const { return att_p_[axis]; }

 private:
  // The estimate at its attitude's sines and cosines (attitude()), which predict() and plate()
  // share with it.
  model::EulerTrig attitude() const;
  VehicleEstimate estimate(const model::EulerTrig& attitude) const;
  PlateKinematics plate_now() const;
  Eigen::Vector3d propagate_rates(double dt_s, const Eigen::Vector3d& command_radps);

  VehicleObserverParams params_;
  bool initialised_ = false;
  bool commanded_ = false;                                            // the last step was driven by a command
  double thrust_mps2_ = 0.0;                                          // the lagged (applied) thrust
  Eigen::Vector3d rates_radps_ = Eigen::Vector3d::Zero();             // the applied rates Omega
  Eigen::Vector3d rate_derivative_radps2_ = Eigen::Vector3d::Zero();  // their derivative Omega'
  std::array<Eigen::Vector3d, 3> trans_x_;
  std::array<Eigen::Matrix3d, 3> trans_p_;
  std::array<Eigen::Vector2d, 3> att_x_;
  std::array<Eigen::Matrix2d, 3> att_p_;
  int rejections_ = 0;
  mutable std::optional<PlateKinematics> plate_;  // plate() since the state last changed
};

}  // namespace gs::estimation
