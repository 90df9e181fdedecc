#include "groundstation/planning/catch_point_predictor.hpp"

#include <algorithm>
#include <cmath>

namespace gs::planning {
namespace {

// Height of the lower end above the catching height, and its rate: d/dt (p_z - L |n_z|) with
// n' = Omega x n (22).
struct LowerEndHeight {
  double height_m;
  double rate_mps;
};

LowerEndHeight lower_end_height(const model::PoleState& s, double catch_height_m,
                                const model::PoleParams& params) {
  const double sign = s.n.z() >= 0.0 ? 1.0 : -1.0;
  const double n_z_dot = s.omega_radps.x() * s.n.y() - s.omega_radps.y() * s.n.x();
  return {s.p_m.z() - params.half_length_m * sign * s.n.z() - catch_height_m,
          s.v_mps.z() - params.half_length_m * sign * n_z_dot};
}

// Root in [0, 1] of the cubic Hermite interpolant with h(0) = h0 > 0, h(1) = h1 <= 0 and end
// slopes d0, d1 (already scaled by the step length); bisection keeps it bracketed. Only the
// first guess: the interpolant is poor when |n_z| has its kink (pole horizontal) in the step.
double hermite_root(double h0, double h1, double d0, double d1) {
  const auto h = [&](double u) {
    const double u2 = u * u;
    const double u3 = u2 * u;
    return (2.0 * u3 - 3.0 * u2 + 1.0) * h0 + (u3 - 2.0 * u2 + u) * d0 + (-2.0 * u3 + 3.0 * u2) * h1 +
           (u3 - u2) * d1;
  };
  double lo = 0.0;
  double hi = 1.0;
  for (int i = 0; i < 30; ++i) {
    const double mid = 0.5 * (lo + hi);
    (h(mid) > 0.0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

constexpr double kHeightTolerance_m = 1e-7;
constexpr int kMaxRefinements = 12;

}  // namespace

CatchPointPrediction predict_catch_point(const model::PoleState& pole, double catch_height_m,
                                         const model::PoleParams& params,
                                         const CatchPointPredictorOptions& options) {
  CatchPointPrediction result;
  if (!(options.step_s > 0.0) || !(options.horizon_s > 0.0) || !std::isfinite(catch_height_m)) {
    return result;
  }
  model::PoleState s0 = model::normalised_pole_state(pole);
  LowerEndHeight g0 = lower_end_height(s0, catch_height_m, params);
  double t0 = 0.0;
  while (t0 < options.horizon_s) {
    const double dt = std::min(options.step_s, options.horizon_s - t0);
    const model::PoleState s1 = model::pole_free_flight_step(s0, dt, params);
    const LowerEndHeight g1 = lower_end_height(s1, catch_height_m, params);
    if (g0.height_m > 0.0 && g1.height_m <= 0.0) {
      // Safeguarded Newton on the crossing time, each iterate an RK4 sub-step of length tau
      // from the step start (the same integrator as the grid), started from the Hermite guess.
      double lo = 0.0;
      double hi = dt;
      model::PoleState s_hi = s1;
      double tau = dt * hermite_root(g0.height_m, g1.height_m, g0.rate_mps * dt, g1.rate_mps * dt);
      model::PoleState s_tau = s1;
      bool converged = false;
      for (int i = 0; i < kMaxRefinements; ++i) {
        s_tau = model::pole_free_flight_step(s0, tau, params);
        const LowerEndHeight g = lower_end_height(s_tau, catch_height_m, params);
        if (std::abs(g.height_m) <= kHeightTolerance_m) {
          converged = true;
          break;
        }
        if (g.height_m > 0.0) {
          lo = tau;
        } else {
          hi = tau;
          s_hi = s_tau;
        }
        const double newton = tau - g.height_m / g.rate_mps;
        tau = (newton > lo && newton < hi) ? newton : 0.5 * (lo + hi);
      }
      if (!converged) {  // the bracket's lower-end-below side, at most ~dt / 2^12 late
        tau = hi;
        s_tau = s_hi;
      }
      result.found = true;
      result.t_s = t0 + tau;
      result.state = s_tau;
      const Eigen::Vector3d lower_end = model::pole_lower_end_m(result.state, params);
      result.x_m = lower_end.x();
      result.y_m = lower_end.y();
      return result;
    }
    s0 = s1;
    g0 = g1;
    t0 += dt;
  }
  return result;
}

}  // namespace gs::planning
