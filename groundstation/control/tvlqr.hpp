// Finite-horizon, time-varying LQR (Section VII-A: the throw and catch manoeuvres are tracked by
// "finite-horizon time-varying LQR controllers, obtained by linearizing the system dynamics (8)
// or (30) about the desired trajectories").
//
// For x' = A(t) x + B(t) u on [t0, tf] with cost x(tf)^T Q_f x(tf) + int x^T Q x + u^T R u dt the
// optimal feedback is u = -K(t) x, K = R^-1 B^T P, with P the solution of the Riccati differential
// equation integrated backward from P(tf) = Q_f:
//   -P' = A^T P + P A - P B R^-1 B^T P + Q.
// It is integrated with classical RK4 in steps of at most max_step_s (explicit: keep
// max_step_s * |fastest closed-loop eigenvalue| well below 2.8; the default 1 ms is far inside
// that for the hover and balancing designs, whose closed-loop eigenvalues have |l| <= 4.7 1/s,
// and keeps the RK4 error at rounding level for them), P is re-symmetrised
// after every step, and P and K are stored on the grid t0, t0 + grid_step_s, ..., tf; between grid
// points they are interpolated linearly, outside [t0, tf] clamped.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <vector>

#include "groundstation/control/linear_system.hpp"

namespace gs::control {

// A(t), B(t) of the linearisation along the nominal trajectory.
using LinearisationFn = std::function<LinearSystem(double t_s)>;

// A(t), B(t) interpolated linearly between samples (times strictly increasing, sizes equal),
// clamped outside. An empty function (solve_tv_lqr then returns no gains) when the samples are
// inconsistent: sizes differ, times not finite or not strictly increasing.
LinearisationFn interpolate_linearisation(std::vector<double> times_s, std::vector<LinearSystem> samples);

struct TvLqrOptions {
  double grid_step_s = 0.005;  // the stored gains: the 200 Hz control period by default
  double max_step_s = 0.001;   // RK4 step bound
};

class TvLqrGains {
 public:
  TvLqrGains() = default;
  TvLqrGains(std::vector<double> times_s, std::vector<Eigen::MatrixXd> gains,
             std::vector<Eigen::MatrixXd> costs);

  Eigen::MatrixXd gain(double t_s) const;  // K(t)
  Eigen::MatrixXd cost(double t_s) const;  // P(t)
  const std::vector<double>& times_s() const { return times_s_; }
  const std::vector<Eigen::MatrixXd>& gains() const { return gains_; }
  const std::vector<Eigen::MatrixXd>& costs() const { return costs_; }
  bool empty() const { return times_s_.empty(); }

 private:
  Eigen::MatrixXd interpolate(const std::vector<Eigen::MatrixXd>& values, double t_s) const;
  std::vector<double> times_s_;
  std::vector<Eigen::MatrixXd> gains_, costs_;
};

// Empty result for inconsistent sizes, non-finite values, tf <= t0 or a non-positive step, or
// when P leaves the finite range (an integration step too long for the system).
TvLqrGains solve_tv_lqr(const LinearisationFn& linearisation, const Eigen::MatrixXd& Q,
                        const Eigen::MatrixXd& R, const Eigen::MatrixXd& Q_final, double t0_s, double tf_s,
                        const TvLqrOptions& options = {});

}  // namespace gs::control
