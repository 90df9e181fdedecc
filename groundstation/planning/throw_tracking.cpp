#include "groundstation/planning/throw_tracking.hpp"

#include <algorithm>
#include <utility>

namespace gs::planning {

namespace planar = model::planar;

Eigen::MatrixXd ThrowTrackingWeights::Q() const {
  return state_tolerance.cwiseAbs2().cwiseInverse().asDiagonal();
}

Eigen::MatrixXd ThrowTrackingWeights::R() const {
  return input_tolerance.cwiseAbs2().cwiseInverse().asDiagonal();
}

Eigen::MatrixXd ThrowTrackingWeights::Qfinal() const { return terminal_factor * Q(); }

ThrowTracker::ThrowTracker(ThrowTrajectory reference, const ThrowTrackingWeights& weights,
                           const control::TvLqrOptions& options)
    : reference_(std::move(reference)) {
  if (reference_.t_s.size() < 3) return;
  const ThrowTrajectory& ref = reference_;
  const control::LinearisationFn linearisation = [&ref](double t_s) {
    const model::PlanarLinearisation lin =
        model::linearise_planar_pole_vehicle(ref.state_at(t_s), ref.input_at(t_s), ref.params);
    return control::LinearSystem{lin.A, lin.B};
  };
  gains_ = control::solve_tv_lqr(linearisation, weights.Q(), weights.R(), weights.Qfinal(), ref.t_s.front(),
                                 ref.t_s.back(), options);
}

Eigen::Matrix<double, 2, 7> ThrowTracker::gain(double t_s) const {
  if (!valid()) return Eigen::Matrix<double, 2, 7>::Zero();
  return gains_.gain(t_s);
}

model::PlanarInput<double> ThrowTracker::command(double t_s, const model::PlanarState<double>& s,
                                                 double feedforward_lead_s) const {
  const double ahead_s = std::min(t_s + std::max(feedforward_lead_s, 0.0), reference_.duration_s());
  return reference_.input_at(ahead_s) - gain(t_s) * (s - reference_.state_at(t_s));
}

model::PlanarInput<double> saturate(const model::PlanarInput<double>& u, const model::VehicleLimits& limits) {
  return model::PlanarInput<double>(
      std::clamp(u(planar::kThrust), limits.a_q_min_mps2, limits.a_q_max_mps2),
      std::clamp(u(planar::kPitchRate), -limits.omega_max_radps, limits.omega_max_radps));
}

}  // namespace gs::planning
