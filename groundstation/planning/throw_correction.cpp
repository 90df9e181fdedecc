#include "groundstation/planning/throw_correction.hpp"

#include <algorithm>
#include <cmath>

namespace gs::planning {

namespace planar = model::planar;

namespace {

// The launch components' places in the planar state.
constexpr int kLaunchIndex[6] = {planar::kX,  planar::kZ,     planar::kVx,
                                 planar::kVz, planar::kAlpha, planar::kAlphaDot};

double blend(double u) { return u * u * (3.0 - 2.0 * u); }

}  // namespace

model::PlanarState<double> reference_shift(const EndShift& end_shift, double tau_s, double duration_s) {
  const double u = duration_s > 0.0 ? std::clamp(tau_s / duration_s, 0.0, 1.0) : 1.0;
  const double sigma = blend(u);
  model::PlanarState<double> shift = model::PlanarState<double>::Zero();
  for (int j = 0; j < 6; ++j) shift(kLaunchIndex[j]) = sigma * end_shift(j);
  return shift;
}

EndShiftSensitivity end_shift_sensitivity(const ThrowTracker& tracker, double step_s) {
  const ThrowTrajectory& plan = tracker.reference();
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
    return (lin.A - bk) * ds + bk * placement * blend(t / duration);
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
  EndShiftSensitivity g;
  for (int i = 0; i < 6; ++i) g.row(i) = ds.row(kLaunchIndex[i]);
  return g;
}

}  // namespace gs::planning
