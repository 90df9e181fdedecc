// Time-varying LQR tracking of the planned throw (Section VII-A: the manoeuvres are tracked by
// "finite-horizon time-varying LQR controllers, obtained by linearizing the system dynamics ...
// about the desired trajectories"). The planar model is linearised along the throw by automatic
// differentiation (linearise_planar_pole_vehicle) and the Riccati differential equation is
// integrated backward from T by control/tvlqr.hpp. The control law is
//   u(t) = u_ref(t) - K(t) (s - s_ref(t)),
// then clamped into the input box of eq. (1), (2) by the caller (saturate()).
#pragma once

#include <Eigen/Core>

#include "groundstation/control/tvlqr.hpp"
#include "groundstation/model/vehicle_limits.hpp"
#include "groundstation/planning/throw_trajectory.hpp"

namespace gs::planning {

// Diagonal weights of the tracking cost int e^T Q e + du^T R du dt + e(T)^T Q_f e(T), chosen by
// Bryson's rule from the error each state may tolerate (the paper leaves LQR weights open, docs/paper-notes.md):
// position 5 cm, velocity 0.2 m/s, pitch 0.1 rad, pole tilt 0.02 rad (the pole is what is being
// thrown and the unstable part), pole rate 0.2 rad/s; inputs 2 m/s^2 of thrust and 2 rad/s of
// pitch rate. The terminal weight is Q_f = Q: the final gain is R^-1 B^T Q_f (400 on the pitch
// error), and a heavier terminal weight raises it beyond what a 200 Hz loop can carry and what
// the Riccati integration's 1 ms explicit step resolves.
struct ThrowTrackingWeights {
  model::PlanarState<double> state_tolerance =
      (model::PlanarState<double>() << 0.05, 0.05, 0.2, 0.2, 0.1, 0.02, 0.2).finished();
  model::PlanarInput<double> input_tolerance = model::PlanarInput<double>(2.0, 2.0);
  double terminal_factor = 1.0;
  bool operator==(const ThrowTrackingWeights&) const = default;

  Eigen::MatrixXd Q() const;
  Eigen::MatrixXd R() const;
  Eigen::MatrixXd Qfinal() const;
};

class ThrowTracker {
 public:
  // Empty (valid() false) when the trajectory is empty or the Riccati integration fails.
  ThrowTracker(ThrowTrajectory reference, const ThrowTrackingWeights& weights = {},
               const control::TvLqrOptions& options = {});

  bool valid() const { return !gains_.empty(); }
  const ThrowTrajectory& reference() const { return reference_; }
  const control::TvLqrGains& gains() const { return gains_; }
  // K(t), 2 x 7: rows (a_q, Omega_y), columns the state order of planar_pole_vehicle.hpp.
  Eigen::Matrix<double, 2, 7> gain(double t_s) const;
  // u_ref(t + lead) - K(t) (s - s_ref(t)), not saturated; the feed-forward is read
  // `feedforward_lead_s` ahead (held at T; planning::throw_step in throw_command.hpp says why).
  model::PlanarInput<double> command(double t_s, const model::PlanarState<double>& s,
                                     double feedforward_lead_s = 0.0) const;

 private:
  ThrowTrajectory reference_;
  control::TvLqrGains gains_;
};

// The input clamped into the box of eq. (1), (2).
model::PlanarInput<double> saturate(const model::PlanarInput<double>& u, const model::VehicleLimits& limits);

}  // namespace gs::planning
