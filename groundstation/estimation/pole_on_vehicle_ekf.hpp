// The on-vehicle modes of the hybrid pole estimator (Section IV): a continuous-time EKF of the
// pole balanced on a quadrocopter, dynamics (30) with the deflections (a, b) of (24), driven by
// the vehicle's estimated motion (the vehicle is estimated separately and taken as known,
// Section IV).
//
// State x = (a, b, a', b', o_x, o_y) (6). The pivot of (23) is where the pole's lower end rests:
// on the catching plate, h = 3 cm above the vehicle's centre of gravity (Section VII-A), at an
// offset o in the plate's plane (plate body axes x, y) that is fixed while the pole rests there
// and is set by where the pole landed. The paper puts the pivot at the centre of gravity; at
// 1 mm motion-capture noise the 3 cm (and a catch off the plate's centre) would dominate the
// innovation, so the filter models both (o as a random walk, allowing slow slip).
//
// Which end rests on the plate is fixed by direction_sign s: the measured direction (the pole's
// body z-axis) is s n, n pointing from the pivot to the centre as in (23).
//
// The pivot's acceleration enters (28), (29) as the specific force f = p'' + g e_z; it is the
// plate centre's (PlateKinematics, with the vehicle's rotation terms), the offset's own rotation
// terms (|o| of a few cm) are left to the process noise, as is the drag on the resting pole.
//
// The normal force the plate must supply to keep the pole (Newton-Euler for the pole centre,
// p_p'' = a_pivot + r'', with r'' from pole_on_vehicle.hpp):
//   F / m_p = f / 4 + mu r,   mu = ((3/4) f . r - |r'|^2) / L^2,
//   F_N / m_p = F . t        (t the plate normal, ^I_B R e_z)
// which is docs/paper-notes.md's a_q - (3/4) a_q sin^2(alpha - theta) - L alpha'^2 cos(alpha - theta) in
// the plane. F_N < 0 means the plate would have to pull: the pole has left (the launch).
#pragma once

#include <Eigen/Dense>

#include "groundstation/estimation/pole_measurement.hpp"
#include "groundstation/estimation/propagation.hpp"
#include "groundstation/estimation/vehicle_observer.hpp"
#include "groundstation/model/pole_on_vehicle.hpp"

namespace gs::estimation {

struct PoleOnVehicleEkfParams {
  model::PoleParams pole;
  double acceleration_psd = 0.05;  // white noise on a'', b'': pivot acceleration error, drag
  double offset_psd = 1e-4;        // random walk of o, m^2 / s (slip on the plate, ~1 cm/s)
  double max_step_s = 0.005;
  // The motion capture's noise, an arena's typical 1 mm / 1 mrad: the filter's gain starts
  // from it, and its evidence for the mode selector is judged on it whatever the gain
  // (set_measurement_sigma).
  double mocap_position_sigma_m = 1e-3;
  double mocap_direction_sigma_rad = 1e-3;
  // The filter gives up (valid() false) when the pole tilts this close to the horizontal:
  // (24) is singular at a^2 + b^2 = L^2, and a pole lying flat does not rest on a plate.
  double max_tilt_rad = 1.35;
};

// How much a vehicle's pole filter trusts the motion capture: trusting_sigma for a vehicle with
// motors up to fast_lag_s in an arena whose poses are no noisier than quiet_noise (the larger of
// metres and radians), wary_sigma from slow_lag_s or noisy_noise, linear between; the larger of
// the two. Measured (`hil campaign --attempts 300 --plant hil/config/envelope.yaml`, the
// vehicles at 5 mm), caught at 1 mm and at 3 mm, by the larger noise and the thrower's lag:
//   noise below 1.5 mm, thrower up to 42 ms: 27 of 29 and 21 of 29
//   noise below 1.5 mm, thrower above 42 ms: 16 of 27 and 23 of 27
//   noise above 1.5 mm, thrower up to 42 ms: 101 of 141 and 111 of 141
//   noise above 1.5 mm, thrower above 42 ms: 36 of 103 and 58 of 103
// and on the built-in plant 400 of 400 at 1 mm, 388 at 3 mm. Slow motors follow the balance and
// the throw late, and noisy poses make the controllers chase noise: a filter that trusts the
// model more gives them less of it.
struct PoleTrust {
  double fast_lag_s = 0.035;
  double slow_lag_s = 0.045;
  double quiet_noise = 1.5e-3;  // above the built-in plant's 0.5-1.5 mm: at 1-1.5 mm it lost 5 of 400
  double noisy_noise = 2.0e-3;
  double trusting_sigma = 1e-3;  // m and rad
  double wary_sigma = 3e-3;
  // Judged again this often: the noise meter's estimate, over its 3-8 s window of poses
  // (mocap_noise.hpp), moves slowly.
  double judge_period_s = 1.0;
};
// `motor_lag_s` NaN: the airframe's; `mocap_noise` NaN: not yet measured (quiet).
double pole_measurement_sigma(double motor_lag_s, double mocap_noise, const PoleTrust& trust);

struct NormalForceEstimate {
  double value_mps2 = 0.0;  // F_N / m_p
  double sigma_mps2 = 0.0;
};

class PoleOnVehicleEkf {
 public:
  static constexpr int kSize = 6;
  enum Index : int { kA = 0, kB = 1, kAdot = 2, kBdot = 3, kOx = 4, kOy = 5 };
  using StateVector = Eigen::Matrix<double, kSize, 1>;
  using StateCovariance = Eigen::Matrix<double, kSize, kSize>;

  explicit PoleOnVehicleEkf(const PoleOnVehicleEkfParams& params = {});

  void reset(const StateVector& state, const StateCovariance& covariance, double direction_sign);

  // Propagates with the pivot's acceleration held over dt_s.
  void predict(double dt_s, const Eigen::Vector3d& pivot_acceleration_mps2,
               Propagation propagation = Propagation::mean_and_covariance);
  PoleInnovation innovation(const PoleMeasurement& measurement, const PlateKinematics& plate) const;
  PoleInnovation update(const PoleMeasurement& measurement, const PlateKinematics& plate);
  // The same with the innovation already computed by innovation() on the current state.
  PoleInnovation update(const PoleMeasurement& measurement, const PlateKinematics& plate,
                        const PoleInnovation& innovation);

  bool valid() const { return valid_; }
  const StateVector& state() const { return x_; }
  const StateCovariance& covariance() const { return p_; }
  double direction_sign() const { return sign_; }
  double last_nis() const { return last_nis_; }
  const PoleOnVehicleEkfParams& params() const { return params_; }
  // The pole's half length L learnt from motion capture (pole_length.hpp).
  void set_pole_half_length(double half_length_m) { params_.pole.half_length_m = half_length_m; }
  // The standard deviations, position (m) and direction (rad), the gain gives the poses: a
  // vehicle with slow motors or in noisy poses trusts them less (PoleTrust). The innovation's
  // NIS and log-likelihood stay on params().mocap_*: the mode selector weighs each mode's
  // filter against the same motion capture, and a filter judged on its own larger sigma gained
  // its log-determinant's 5.5 nats a frame at 3 mm (the free-flight candidate, judged on 1 mm,
  // won the switch every few frames on the envelope's slow-motored corner: 139 times an
  // attempt).
  void set_measurement_sigma(double position_m, double direction_rad) {
    gain_position_sigma_m_ = position_m;
    gain_direction_sigma_rad_ = direction_rad;
  }
  double gain_position_sigma_m() const { return gain_position_sigma_m_; }
  double gain_direction_sigma_rad() const { return gain_direction_sigma_rad_; }

  model::PoleOnVehicleState pole() const { return {x_(kA), x_(kB), x_(kAdot), x_(kBdot)}; }
  Eigen::Vector2d offset_m() const { return x_.segment<2>(kOx); }
  // Where the pole's lower end rests (the pivot), for a plate pose.
  Eigen::Vector3d pivot_m(const PlateKinematics& plate) const;
  // The pole as a free-flight state (21) in the measurement's direction convention, and the
  // Jacobian of that state (p, v, n, Omega) with respect to x.
  model::PoleState free_flight_state(const PlateKinematics& plate) const;
  Eigen::Matrix<double, 12, kSize> free_flight_jacobian(const PlateKinematics& plate) const;

  // The plate's normal force (see the header comment), with a standard deviation from the
  // state covariance and the plate's acceleration variance.
  NormalForceEstimate normal_force(const PlateKinematics& plate) const;

  // Continuous-time Jacobian of (28), (29) for a pivot acceleration, exposed for tests.
  StateCovariance jacobian(const Eigen::Vector3d& pivot_acceleration_mps2) const;

 private:
  void step(double h, const Eigen::Vector3d& pivot_acceleration_mps2, Propagation propagation);
  bool check_valid();
  LinearisedPoleMeasurement<kSize> linearise(const PoleMeasurement& m, const PlateKinematics& plate) const;

  PoleOnVehicleEkfParams params_;
  double gain_position_sigma_m_;
  double gain_direction_sigma_rad_;
  StateVector x_ = StateVector::Zero();
  StateCovariance p_ = StateCovariance::Identity();
  double sign_ = 1.0;
  bool valid_ = false;
  double last_nis_ = 0.0;
};

// The plate-normal force per pole mass for a pole state on a pivot with specific force f
// (= pivot acceleration + g e_z) and plate normal t (see the header comment).
double pole_normal_force_per_mass_mps2(const model::PoleOnVehicleState& pole,
                                       const Eigen::Vector3d& specific_force_mps2,
                                       const Eigen::Vector3d& plate_normal, const model::PoleParams& params);

}  // namespace gs::estimation
