// The free-flight mode of the hybrid pole estimator (Section IV): a continuous-time extended
// Kalman filter of the pole dynamics (20) with discrete motion-capture measurements.
//
// State x = (p_p, p_p', n, Omega_p, k) (13): the pole state (21) and a drag scale k that
// multiplies all three drag coefficients of (10), (11), (15). The drag is large (about 40 % of
// the pole's weight at 5 m/s broadside) and its coefficients are uncertain, so the filter can
// estimate it online (estimate_drag_scale; with it off k stays at its seed value).
//
// The constraints |n| = 1 and Omega . n = 0 (pole_free_flight.hpp) are kept by normalising the
// state after every step and projecting the covariance with the Jacobian of that normalisation,
// so P has rank 11 (10 without k) and the redundant directions carry no spurious uncertainty.
//
// Prediction: the state by RK4 of (20) (model::pole_free_flight_step), the covariance by the
// continuous-time Riccati equation over the same step, P' = F P + P F^T + G Q G^T, solved with
// Phi = I + F h + (F h)^2 / 2 and the matching second-order noise integral. F is the Jacobian of
// (16), (19), (22); the drag parts by forward differences of model::pole_drag (eq. (10)-(15)
// have no tidy closed-form derivative), the kinematic parts analytically.
#pragma once

#include <Eigen/Dense>

#include "groundstation/estimation/pole_measurement.hpp"
#include "groundstation/estimation/propagation.hpp"
#include "groundstation/model/pole_free_flight.hpp"

namespace gs::estimation {

struct PoleFreeFlightEkfParams {
  model::PoleParams pole;  // the nominal drag coefficients are those of k = 1
  // Unmodelled accelerations: what (10)-(22) leave out beyond the drag scale k (the quadrature
  // of a real plant's drag, the tube's own small inertia, air currents), a few mm/s^2 and
  // mrad/s^2. Small: on a flight that follows the model a larger process noise makes the filter
  // conservative (NEES below its band, tests/groundstation/state_estimator_test.cpp).
  double acceleration_psd = 1e-6;          // white noise on p_p', (m/s^2)^2 / Hz
  double angular_acceleration_psd = 1e-6;  // on Omega_p' (normal to n), (rad/s^2)^2 / Hz
  bool estimate_drag_scale = true;
  double drag_scale_psd = 1e-4;  // random walk of k, 1 / s
  double max_step_s = 0.005;     // longer predictions are split into such steps
  double mocap_position_sigma_m = 1e-3;
  double mocap_direction_sigma_rad = 1e-3;
};

class PoleFreeFlightEkf {
 public:
  static constexpr int kSize = 13;
  enum Index : int { kP = 0, kV = 3, kN = 6, kW = 9, kK = 12 };
  using StateCovariance = Eigen::Matrix<double, kSize, kSize>;
  // The pole part (p, v, n, Omega) only, as the mode conversions use it.
  using PoleCovariance = Eigen::Matrix<double, 12, 12>;

  explicit PoleFreeFlightEkf(const PoleFreeFlightEkfParams& params = {});

  // Starts from a state, its 12 x 12 covariance and a drag scale with its standard deviation
  // (ignored, i.e. k fixed, unless estimate_drag_scale).
  void reset(const model::PoleState& state, const PoleCovariance& covariance, double drag_scale,
             double drag_scale_sigma);

  void predict(double dt_s, Propagation propagation = Propagation::mean_and_covariance);
  PoleInnovation innovation(const PoleMeasurement& measurement) const;
  PoleInnovation update(const PoleMeasurement& measurement);
  // The same with the measurement's innovation already computed by innovation() on the current
  // state (the hybrid estimator evaluates every mode first, then corrects: one linearisation).
  PoleInnovation update(const PoleMeasurement& measurement, const PoleInnovation& innovation);

  const model::PoleState& state() const { return state_; }
  double drag_scale() const { return drag_scale_; }
  const StateCovariance& covariance() const { return p_; }
  PoleCovariance pole_covariance() const { return p_.topLeftCorner<12, 12>(); }
  double last_nis() const { return last_nis_; }
  const PoleFreeFlightEkfParams& params() const { return params_; }
  // The pole's half length L learnt from motion capture (pole_length.hpp).
  void set_pole_half_length(double half_length_m) { params_.pole.half_length_m = half_length_m; }
  // The model with the drag coefficients scaled by the current k (for predictions elsewhere).
  model::PoleParams scaled_model() const;

  // Continuous-time Jacobian df/dx of (20) with the drag scale, exposed for tests.
  StateCovariance jacobian() const;

 private:
  void step(double h, Propagation propagation);
  void normalise();
  LinearisedPoleMeasurement<kSize> linearise(const PoleMeasurement& m) const;

  PoleFreeFlightEkfParams params_;
  model::PoleState state_;
  double drag_scale_ = 1.0;
  StateCovariance p_ = StateCovariance::Identity();
  double last_nis_ = 0.0;
};

// Normalised estimation error squared over the 10 physical degrees of freedom (position,
// velocity, the 2 tangent components of n and of Omega; k excluded): chi-square with 10 dof
// for a consistent filter.
double free_flight_nees(const PoleFreeFlightEkf& ekf, const model::PoleState& truth);

}  // namespace gs::estimation
