#include "groundstation/planning/height_shift.hpp"

#include <algorithm>
#include <cmath>

namespace gs::planning {
namespace {

struct Quintic {
  double c[6];
};

// From (z0, v0, a0) to (z1, 0, 0) over T: the quintic's closed form.
Quintic quintic(const HeightShiftSample& s, double z1, double T) {
  const double h = z1 - s.z_m, v0 = s.dz_mps, a0 = s.ddz_mps2;
  const double T2 = T * T, T3 = T2 * T;
  return {{s.z_m, v0, 0.5 * a0, (20.0 * h - 12.0 * v0 * T - 3.0 * a0 * T2) / (2.0 * T3),
           (-30.0 * h + 16.0 * v0 * T + 3.0 * a0 * T2) / (2.0 * T3 * T),
           (12.0 * h - 6.0 * v0 * T - a0 * T2) / (2.0 * T3 * T2)}};
}

double accel(const Quintic& q, double x) {
  return 2.0 * q.c[2] + x * (6.0 * q.c[3] + x * (12.0 * q.c[4] + x * 20.0 * q.c[5]));
}

// The largest |z''| on [0, T]: at the ends or where z''' = 6 c3 + 24 c4 x + 60 c5 x^2 vanishes.
double peak_accel(const Quintic& q, double T) {
  double peak = std::max(std::abs(accel(q, 0.0)), std::abs(accel(q, T)));
  const double a = 60.0 * q.c[5], b = 24.0 * q.c[4], c = 6.0 * q.c[3];
  const auto consider = [&](double x) {
    if (x > 0.0 && x < T) peak = std::max(peak, std::abs(accel(q, x)));
  };
  if (std::abs(a) < 1e-12) {
    if (std::abs(b) > 1e-12) consider(-c / b);
  } else if (const double d = b * b - 4.0 * a * c; d >= 0.0) {
    consider((-b + std::sqrt(d)) / (2.0 * a));
    consider((-b - std::sqrt(d)) / (2.0 * a));
  }
  return peak;
}

}  // namespace

void HeightShift::retarget(double now_s, double target_m, double end_s, double max_accel_mps2) {
  const double T = end_s - now_s;
  if (!(T >= min_duration_s) || !std::isfinite(target_m) || !(max_accel_mps2 > 0.0)) return;
  const HeightShiftSample s = at(now_s);
  // The way to the target if the thrust allows it, else the largest part of the change from the
  // current course's target that it does (the current course itself is lambda = 0).
  const auto aim = [&](double lambda) {
    return lambda == 1.0 ? target_m : target_m_ + lambda * (target_m - target_m_);
  };
  const auto plan = [&](double lambda) { return quintic(s, aim(lambda), T); };
  double lambda = 1.0;
  if (peak_accel(plan(1.0), T) > max_accel_mps2) {
    double lo = 0.0, hi = 1.0;
    for (int i = 0; i < 30; ++i) {
      const double mid = 0.5 * (lo + hi);
      (peak_accel(plan(mid), T) > max_accel_mps2 ? hi : lo) = mid;
    }
    lambda = lo;
  }
  const Quintic q = plan(lambda);
  std::copy(std::begin(q.c), std::end(q.c), c_);
  target_m_ = aim(lambda);
  start_s_ = now_s;
  end_s_ = end_s;
}

HeightShiftSample HeightShift::at(double t_s) const {
  if (!(end_s_ > start_s_) || t_s >= end_s_) return {target_m_, 0.0, 0.0, 0.0};
  const double x = std::max(t_s - start_s_, 0.0);
  const double* c = c_;
  HeightShiftSample s;
  s.z_m = c[0] + x * (c[1] + x * (c[2] + x * (c[3] + x * (c[4] + x * c[5]))));
  s.dz_mps = c[1] + x * (2.0 * c[2] + x * (3.0 * c[3] + x * (4.0 * c[4] + x * 5.0 * c[5])));
  s.ddz_mps2 = 2.0 * c[2] + x * (6.0 * c[3] + x * (12.0 * c[4] + x * 20.0 * c[5]));
  s.jerk_mps3 = 6.0 * c[3] + x * (24.0 * c[4] + x * 60.0 * c[5]);
  return s;
}

CatchReference shifted(const CatchReference& reference, const HeightShiftSample& shift) {
  CatchReference out = reference;
  out.position_m.z() += shift.z_m;
  out.velocity_mps.z() += shift.dz_mps;
  out.acceleration_mps2.z() += shift.ddz_mps2;
  out.jerk_mps3.z() += shift.jerk_mps3;
  const NominalInputs u = nominal_inputs(out.acceleration_mps2, out.jerk_mps3, out.yaw_rad);
  out.thrust_mps2 = u.thrust_mps2;
  out.body_rates_radps = u.body_rates_radps;
  out.roll_rad = u.roll_rad;
  out.pitch_rad = u.pitch_rad;
  return out;
}

}  // namespace gs::planning
