#include "groundstation/adaptation/throw_learning.hpp"

#include <algorithm>
#include <cmath>

namespace gs::adaptation {

namespace planar = model::planar;

LaunchVector launch_vector(const planning::PlanarLaunchState& s) {
  LaunchVector v;
  v << s.x_m, s.z_m, s.vx_mps, s.vz_mps, s.alpha_rad, s.alpha_dot_radps;
  return v;
}

planning::PlanarLaunchState launch_state(const LaunchVector& v) {
  return {v(0), v(1), v(2), v(3), v(4), v(5)};
}

namespace {

// The launch components' places in the planar state.
constexpr int kLaunchIndex[6] = {planar::kX,  planar::kZ,     planar::kVx,
                                 planar::kVz, planar::kAlpha, planar::kAlphaDot};

}  // namespace

LaunchMatrix throw_sensitivity(const planning::ThrowTracker& tracker, double step_s) {
  const planning::ThrowTrajectory& plan = tracker.reference();
  const double duration = plan.duration_s();
  const int steps = std::max(1, static_cast<int>(std::ceil(duration / step_s)));
  const double h = duration / steps;
  using Block = Eigen::Matrix<double, planar::kStateSize, 6>;
  // Column j: the deviation caused by a unit correction of launch component j.
  Block placement = Block::Zero();
  for (int j = 0; j < 6; ++j) placement(kLaunchIndex[j], j) = 1.0;
  const auto derivative = [&](double t, const Block& ds) -> Block {
    const model::PlanarLinearisation lin =
        model::linearise_planar_pole_vehicle(plan.state_at(t), plan.input_at(t), plan.params);
    const Eigen::Matrix<double, planar::kStateSize, planar::kStateSize> bk = lin.B * tracker.gain(t);
    const double u = t / duration;
    return (lin.A - bk) * ds + bk * placement * (u * u * (3.0 - 2.0 * u));
  };
  Block ds = Block::Zero();
  for (int i = 0; i < steps; ++i) {  // RK4
    const double t = i * h;
    const Block k1 = derivative(t, ds);
    const Block k2 = derivative(t + 0.5 * h, ds + 0.5 * h * k1);
    const Block k3 = derivative(t + 0.5 * h, ds + 0.5 * h * k2);
    const Block k4 = derivative(t + h, ds + h * k3);
    ds += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
  }
  LaunchMatrix g;
  for (int i = 0; i < 6; ++i) g.row(i) = ds.row(kLaunchIndex[i]);
  return g;
}

LaunchMatrix damped_inverse(const LaunchMatrix& g, double lambda) {
  return (g.transpose() * g + lambda * LaunchMatrix::Identity()).inverse() * g.transpose();
}

ThrowCorrection learn_from_throw(const ThrowCorrection& correction, const planning::PlanarLaunchState& flown,
                                 const planning::PlanarLaunchState& planned,
                                 const ThrowLearningSettings& settings,
                                 const LaunchMatrix& inverse_sensitivity) {
  const LaunchVector error = launch_vector(flown) - launch_vector(planned);
  if (!error.allFinite()) return correction;
  LaunchVector bound;
  bound << settings.max_position_m, settings.max_position_m, settings.max_speed_mps, settings.max_speed_mps,
      settings.max_angle_rad, settings.max_rate_radps;
  // A launch this far from the plan is a failed or spoiled throw (pushed aside, a gust), not a
  // model error that repeats.
  if ((error.cwiseAbs().array() > bound.array()).any()) return correction;
  ThrowCorrection next = correction;
  next.end_shift =
      (correction.end_shift - settings.gain * inverse_sensitivity * error).cwiseMax(-bound).cwiseMin(bound);
  ++next.throws;
  return next;
}

model::PlanarState<double> reference_shift(const ThrowCorrection& correction, double tau_s,
                                           double duration_s) {
  const double u = duration_s > 0.0 ? std::clamp(tau_s / duration_s, 0.0, 1.0) : 1.0;
  const double sigma = u * u * (3.0 - 2.0 * u);
  const LaunchVector& c = correction.end_shift;
  model::PlanarState<double> shift = model::PlanarState<double>::Zero();
  shift(planar::kX) = sigma * c(0);
  shift(planar::kZ) = sigma * c(1);
  shift(planar::kVx) = sigma * c(2);
  shift(planar::kVz) = sigma * c(3);
  shift(planar::kAlpha) = sigma * c(4);
  shift(planar::kAlphaDot) = sigma * c(5);
  return shift;
}

}  // namespace gs::adaptation
