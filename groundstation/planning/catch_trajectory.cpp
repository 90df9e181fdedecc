#include "groundstation/planning/catch_trajectory.hpp"

#include <algorithm>
#include <cmath>

namespace gs::planning {

namespace {

// Where the min-snap shape's acceleration and jerk peak (exact; see min_snap_shape):
// d3 = 0 inside (0,1) at tau = (5 -+ sqrt 5)/10, d4 = 0 at tau = 1/2 and (5 -+ sqrt 15)/10.
const double kSqrt5 = std::sqrt(5.0);
const double kSqrt15 = std::sqrt(15.0);
const std::array<double, 2> kAccelPeakTau = {(5.0 - kSqrt5) / 10.0, (5.0 + kSqrt5) / 10.0};
const std::array<double, 3> kJerkPeakTau = {(5.0 - kSqrt15) / 10.0, 0.5, (5.0 + kSqrt15) / 10.0};

// Subdivision floor and the scan step used to locate the worst violation.
constexpr double kMinSection_s = 1e-3;
constexpr double kScanStep_s = 1e-3;

bool allFinite(const CatchTrajectoryParams& p) {
  return p.start_xy_m.allFinite() && p.target_xy_m.allFinite() && std::isfinite(p.catch_height_m) &&
         std::isfinite(p.t_xy_s) && std::isfinite(p.a_max_mps2) && std::isfinite(p.k_max_mps3) &&
         std::isfinite(p.yaw_rad) && std::isfinite(p.gravity_mps2) && std::isfinite(p.xy_lead_s);
}

}  // namespace

std::string_view to_string(CatchParamError error) {
  switch (error) {
    case CatchParamError::none: return "ok";
    case CatchParamError::non_finite: return "a parameter is not finite";
    case CatchParamError::non_positive_duration: return "T_xy must be positive";
    case CatchParamError::negative_accel: return "a_max must be non-negative";
    case CatchParamError::non_positive_jerk: return "k_max must be positive";
    case CatchParamError::non_positive_gravity: return "gravity must be positive";
    case CatchParamError::hold_too_short: return "T_xy must be at least a_max / k_max (Fig. 6)";
    case CatchParamError::bad_lead:
      return "the xy lead must be between 0 and t3, and a lead needs a_max below g";
  }
  return "unknown";
}

CatchParamError validate(const CatchTrajectoryParams& p) {
  if (!allFinite(p)) return CatchParamError::non_finite;
  if (!(p.t_xy_s > 0.0)) return CatchParamError::non_positive_duration;
  if (!(p.a_max_mps2 >= 0.0)) return CatchParamError::negative_accel;
  if (!(p.k_max_mps3 > 0.0)) return CatchParamError::non_positive_jerk;
  if (!(p.gravity_mps2 > 0.0)) return CatchParamError::non_positive_gravity;
  // The hold h = T_xy - a_max/k_max must be >= 0; a relative tolerance keeps T_xy = a/k valid.
  if (p.t_xy_s < p.a_max_mps2 / p.k_max_mps3 * (1.0 - 1e-12)) return CatchParamError::hold_too_short;
  // t3 = 2 a_max / k_max + T_xy ((48) less the last T_xy). With a lead the xy correction runs
  // in the dive too, where the check's bounds need the vertical specific force g - a_max > 0.
  const double t3 = 2.0 * p.a_max_mps2 / p.k_max_mps3 + p.t_xy_s;
  if (!(p.xy_lead_s >= 0.0) || p.xy_lead_s > t3 || (p.xy_lead_s > 0.0 && !(p.a_max_mps2 < p.gravity_mps2)))
    return CatchParamError::bad_lead;
  return CatchParamError::none;
}

std::string_view to_string(Feasibility verdict) {
  switch (verdict) {
    case Feasibility::feasible: return "feasible";
    case Feasibility::thrust_too_high: return "thrust_too_high";
    case Feasibility::thrust_too_low: return "thrust_too_low";
    case Feasibility::rates_too_high: return "rates_too_high";
  }
  return "unknown";
}

const LimitViolation& FeasibilityVerdict::primary() const {
  switch (reason) {
    case Feasibility::thrust_too_low: return thrust_low;
    case Feasibility::rates_too_high: return rates;
    default: return thrust_high;
  }
}

// ---------------------------------------------------------------------------------------------
// Minimum snap, eqs. (43)-(45).

namespace min_snap_shape {
double sigma(double tau) {
  const double t2 = tau * tau;
  return t2 * t2 * (35.0 + tau * (-84.0 + tau * (70.0 - 20.0 * tau)));
}
double d1(double tau) {
  const double u = tau * (1.0 - tau);
  return 140.0 * u * u * u;
}
double d2(double tau) {
  const double u = tau * (1.0 - tau);
  return 420.0 * u * u * (1.0 - 2.0 * tau);
}
double d3(double tau) {
  const double u = tau * (1.0 - tau);
  return 840.0 * u * (1.0 - 5.0 * u);  // 5 tau^2 - 5 tau + 1 = 1 - 5 u
}
double d4(double tau) { return 840.0 * (1.0 + tau * (-12.0 + tau * (30.0 - 20.0 * tau))); }
}  // namespace min_snap_shape

MinSnapSample MinSnapAxis::operator()(double t_s) const {
  MinSnapSample s;
  if (t_s < 0.0) {
    s.q = q0;
    return s;
  }
  if (t_s > duration_s) {
    s.q = qT;
    return s;
  }
  const double T = duration_s;
  const double tau = t_s / T;
  const double d = qT - q0;
  s.q = q0 + d * min_snap_shape::sigma(tau);
  s.dq = d / T * min_snap_shape::d1(tau);
  s.ddq = d / (T * T) * min_snap_shape::d2(tau);
  s.jerk = d / (T * T * T) * min_snap_shape::d3(tau);
  s.snap = d / (T * T * T * T) * min_snap_shape::d4(tau);
  return s;
}

// ---------------------------------------------------------------------------------------------
// The z manoeuvre, Fig. 6 and eqs. (48), (49).

MinimaxZManoeuvre::MinimaxZManoeuvre(double z_T_m, double t_xy_s, double a_max_mps2, double k_max_mps3) {
  const double ramp = a_max_mps2 / k_max_mps3;       // a_max / k_max
  const double hold = std::max(0.0, t_xy_s - ramp);  // [t1,t2] and [t3,t4]
  const std::array<double, 5> durations = {ramp, hold, 2.0 * ramp, hold, ramp};
  jerk_ = {-k_max_mps3, 0.0, k_max_mps3, 0.0, -k_max_mps3};
  // eq. (49)
  z_[0] = z_T_m + (a_max_mps2 * a_max_mps2 * t_xy_s + a_max_mps2 * k_max_mps3 * t_xy_s * t_xy_s) / k_max_mps3;
  v_[0] = 0.0;
  a_[0] = 0.0;
  t_[0] = 0.0;
  for (int i = 0; i < 5; ++i) {
    const double d = durations[i];
    t_[i + 1] = t_[i] + d;
    const double z = z_[i] + v_[i] * d + 0.5 * a_[i] * d * d + jerk_[i] * d * d * d / 6.0;
    const double v = v_[i] + a_[i] * d + 0.5 * jerk_[i] * d * d;
    const double a = a_[i] + jerk_[i] * d;
    if (i < 4) {
      z_[i + 1] = z;
      v_[i + 1] = v;
      a_[i + 1] = a;
    } else {
      z_end_ = z;
    }
  }
}

ZSample MinimaxZManoeuvre::operator()(double t_s) const {
  ZSample s;
  if (t_s < 0.0) {
    s.z = z_[0];
    return s;
  }
  if (t_s > t_[5]) {
    s.z = z_end_;
    return s;
  }
  int i = 4;
  while (i > 0 && t_s < t_[i]) --i;
  const double d = t_s - t_[i];
  s.jerk = jerk_[i];
  s.ddz = a_[i] + jerk_[i] * d;
  s.dz = v_[i] + a_[i] * d + 0.5 * jerk_[i] * d * d;
  s.z = z_[i] + v_[i] * d + 0.5 * a_[i] * d * d + jerk_[i] * d * d * d / 6.0;
  return s;
}

// ---------------------------------------------------------------------------------------------
// Nominal inputs, eqs. (46), (47), (4), (5).

NominalInputs nominal_inputs(const Eigen::Vector3d& acceleration_mps2, const Eigen::Vector3d& jerk_mps3,
                             double yaw_rad, double gravity_mps2) {
  NominalInputs out;
  const Eigen::Vector3d f = acceleration_mps2 + Eigen::Vector3d(0.0, 0.0, gravity_mps2);  // (46)
  const double f_norm = f.norm();
  out.thrust_mps2 = f_norm;
  if (!(f_norm > 1e-12)) return out;  // free fall: the attitude is undetermined

  // (4) with (3): the body z-axis I_B R e_z = f/|f|. In the yaw-rotated frame R_z(psi) f the
  // z-axis is (sin(theta) cos(phi), -sin(phi), cos(theta) cos(phi)).
  const double cy = std::cos(yaw_rad), sy = std::sin(yaw_rad);
  const Eigen::Vector3d fy(cy * f.x() + sy * f.y(), -sy * f.x() + cy * f.y(), f.z());
  out.pitch_rad = std::atan2(fy.x(), fy.z());
  out.roll_rad = std::atan2(-fy.y(), std::hypot(fy.x(), fy.z()));

  // (47): (Omega_y, -Omega_x, 0) = B_I R d/dt(f/|f|), B_I R = R_x(phi) R_y(theta) R_z(psi).
  const Eigen::Vector3d z_dot = jerk_mps3 / f_norm - f * (f.dot(jerk_mps3) / (f_norm * f_norm * f_norm));
  const double cp = std::cos(out.pitch_rad), sp = std::sin(out.pitch_rad);
  const double cr = std::cos(out.roll_rad), sr = std::sin(out.roll_rad);
  Eigen::Matrix3d Rx, Ry, Rz;
  Rx << 1, 0, 0, 0, cr, sr, 0, -sr, cr;
  Ry << cp, 0, -sp, 0, 1, 0, sp, 0, cp;
  Rz << cy, sy, 0, -sy, cy, 0, 0, 0, 1;
  const Eigen::Vector3d r = Rx * (Ry * (Rz * z_dot));
  const double omega_y = r.x();
  const double omega_x = -r.y();
  // (5) with psi' = 0: psi' = (sin(phi) Omega_y + cos(phi) Omega_z) / cos(theta).
  const double omega_z = -sr / cr * omega_y;
  out.body_rates_radps = Eigen::Vector3d(omega_x, omega_y, omega_z);
  return out;
}

// ---------------------------------------------------------------------------------------------
// The catch trajectory.

std::optional<CatchTrajectory> CatchTrajectory::create(const CatchTrajectoryParams& params) {
  if (validate(params) != CatchParamError::none) return std::nullopt;
  return CatchTrajectory(params);
}

CatchTrajectory::CatchTrajectory(const CatchTrajectoryParams& params)
    : params_(params), z_(params.catch_height_m, params.t_xy_s, params.a_max_mps2, params.k_max_mps3) {
  x_ = MinSnapAxis{params.start_xy_m.x(), params.target_xy_m.x(), xy_duration_s()};
  y_ = MinSnapAxis{params.start_xy_m.y(), params.target_xy_m.y(), xy_duration_s()};
  const Eigen::Vector2d d = params.target_xy_m - params.start_xy_m;
  distance_m_ = d.norm();
  if (distance_m_ > 0.0) {
    const double cy = std::cos(params.yaw_rad), sy = std::sin(params.yaw_rad);
    dir_c_ = (cy * d.x() + sy * d.y()) / distance_m_;
    dir_s_ = (-sy * d.x() + cy * d.y()) / distance_m_;
  }
}

CatchReference CatchTrajectory::reference(double t_s) const {
  CatchReference ref;
  ref.t_s = t_s;
  const double t_xy = t_s - xy_start_time_s();
  const MinSnapSample sx = x_(t_xy);
  const MinSnapSample sy = y_(t_xy);
  const ZSample sz = z_(t_s);
  ref.position_m = Eigen::Vector3d(sx.q, sy.q, sz.z);
  ref.velocity_mps = Eigen::Vector3d(sx.dq, sy.dq, sz.dz);
  ref.acceleration_mps2 = Eigen::Vector3d(sx.ddq, sy.ddq, sz.ddz);
  ref.jerk_mps3 = Eigen::Vector3d(sx.jerk, sy.jerk, sz.jerk);
  const NominalInputs in =
      nominal_inputs(ref.acceleration_mps2, ref.jerk_mps3, params_.yaw_rad, params_.gravity_mps2);
  ref.thrust_mps2 = in.thrust_mps2;
  ref.body_rates_radps = in.body_rates_radps;
  ref.roll_rad = in.roll_rad;
  ref.pitch_rad = in.pitch_rad;
  ref.yaw_rad = params_.yaw_rad;
  return ref;
}

// In the xy phase the horizontal acceleration is h(t) times the fixed unit direction d, with
// h = D/T^2 sigma''(tau) (D the travel distance), so the motion lies in the vertical plane
// through d. With w = z'' + g, J = h' w - h w', N^2 = h^2 + w^2 and d = (c, s) in the yaw frame,
// (4), (47) and psi' = 0 give in closed form (theta = atan2(h c, w), sin(phi) = -h s / N):
//   Omega_x = phi'             = -s w J / (N^2 sqrt(h^2 c^2 + w^2))
//   Omega_y = cos(phi) theta'  =  c J   / (N   sqrt(h^2 c^2 + w^2))
//   Omega_z = -sin(phi) theta' =  h s c J / (N (h^2 c^2 + w^2))
// and Omega_x^2 + Omega_y^2 = (J / N^2)^2 = |d/dt (f/|f|)|^2.
CatchTrajectory::PointInputs CatchTrajectory::xy_phase_inputs(double t_s) const {
  const double T = xy_duration_s();
  const double tau = std::clamp((t_s - xy_start_time_s()) / T, 0.0, 1.0);
  const double h = distance_m_ / (T * T) * min_snap_shape::d2(tau);
  const double h_dot = distance_m_ / (T * T * T) * min_snap_shape::d3(tau);
  const ZSample sz = z_(t_s);
  const double w = sz.ddz + params_.gravity_mps2;
  const double w_dot = sz.jerk;
  const double J = h_dot * w - h * w_dot;
  const double n2 = h * h + w * w;
  const double m2 = h * h * dir_c_ * dir_c_ + w * w;
  const double n = std::sqrt(n2), m = std::sqrt(m2);
  const std::array<double, 3> omega = {std::abs(dir_s_ * w * J / (n2 * m)), std::abs(dir_c_ * J / (n * m)),
                                       std::abs(h * dir_s_ * dir_c_ * J / (n * m2))};
  const int axis = static_cast<int>(std::max_element(omega.begin(), omega.end()) - omega.begin());
  return {n, omega[axis], axis};
}

// The bounds used on a section [ta, tb] of one phase with xy moving (w = z'' + g is linear in t,
// w' constant, and w >= g - a_max > 0: z'' >= 0 in [t3, t5], and validate() asks a_max < g of a
// lead into the dive):
//   h  in [h_min, h_max]     exact: sigma'' at the ends and at its interior extremes
//   h' in [hd_min, hd_max]   exact: sigma''' at the ends and at its interior extremes
//   w  in [w_lo, w_hi]       exact (linear)
//   J = h' w - h w'          by interval arithmetic from the three ranges
//   a_q^2 = h^2 + w^2 in [h_lo^2 + w_lo^2, h_hi^2 + w_hi^2]   (h_lo, h_hi: range of |h|)
//   N >= n_lo = sqrt(h_lo^2 + w_lo^2),  sqrt(h^2 c^2 + w^2) >= m_lo = sqrt(h_lo^2 c^2 + w_lo^2)
//   |Omega_x| <= |s| w_hi |J| / (n_lo^2 m_lo), |Omega_y| <= |c| |J| / (n_lo m_lo),
//   |Omega_z| <= h_hi |s c| |J| / (n_lo m_lo^2)                  (the closed forms above)
//   and also |Omega_x|, |Omega_y| <= |J| / N^2 <= |nu| / |f| (their squares sum to (J/N^2)^2),
//   |Omega_z| = |tan(phi)| |Omega_y| <= (|h| / w) |J| / N^2.
// Every bound tends to the exact value as the section shrinks, so only a limit met within
// O(section length) stays undecided down to the 1 ms floor.
FeasibilityVerdict CatchTrajectory::check_feasibility(const InputLimits& limits) const {
  FeasibilityVerdict verdict;
  const double g = params_.gravity_mps2;
  const auto& tz = z_.phase_times_s();
  const double T = xy_duration_s();
  const double t3 = xy_start_time_s();  // the xy start (t3 itself without a lead)

  // Before the xy start, xy at rest: a_q = z'' + g, piecewise linear, so its extremes are at the
  // phase boundaries and the xy start; no rates. The signed value is used so that a_max > g (a
  // thrust that would have to point down) reads as too low.
  double rest_hi = g, rest_hi_t = 0.0, rest_lo = g, rest_lo_t = 0.0;
  auto rest_extremes = [&](double t) {
    const double w = z_(t).ddz + g;
    if (w > rest_hi) rest_hi = w, rest_hi_t = t;
    if (w < rest_lo) rest_lo = w, rest_lo_t = t;
  };
  for (const double t : tz)
    if (t <= t3) rest_extremes(t);
  rest_extremes(t3);
  const bool low = rest_lo < limits.a_q_min_mps2;
  const bool high = rest_hi > limits.a_q_max_mps2;

  // The phases from the xy start to t5: bisection with a fixed stack (depth <= log2(T_xy / 1 ms)
  // + 1 per phase).
  const double h_scale = distance_m_ / (T * T);
  const double j_scale = distance_m_ / (T * T * T);
  const double thrust_max2 = limits.a_q_max_mps2 * limits.a_q_max_mps2;
  const double thrust_min2 = limits.a_q_min_mps2 * limits.a_q_min_mps2;
  const double rate_max = limits.omega_max_radps;
  auto violates = [&](const PointInputs& p) {
    return p.thrust_mps2 > limits.a_q_max_mps2 || p.thrust_mps2 < limits.a_q_min_mps2 ||
           p.rate_radps > rate_max;
  };
  struct Section {
    double ta, tb;
  };
  std::array<Section, 96> stack;
  double found_t = -1.0;  // where the bisection met an exact violation
  for (int phase = 0; phase < 5 && !(low || high || found_t >= 0.0); ++phase) {
    const Section moving{std::max(tz[phase], t3), tz[phase + 1]};  // the phase's part with xy moving
    const double w_dot = z_.phase_jerks_mps3()[phase];
    int top = 0;
    if (moving.tb > moving.ta) stack[top++] = moving;
    while (top > 0 && found_t < 0.0) {
      const Section s = stack[--top];
      const double tau_a = std::clamp((s.ta - t3) / T, 0.0, 1.0);
      const double tau_b = std::clamp((s.tb - t3) / T, 0.0, 1.0);
      double h_min = std::min(min_snap_shape::d2(tau_a), min_snap_shape::d2(tau_b));
      double h_max = std::max(min_snap_shape::d2(tau_a), min_snap_shape::d2(tau_b));
      for (double tau : kAccelPeakTau) {
        if (tau > tau_a && tau < tau_b) {
          h_min = std::min(h_min, min_snap_shape::d2(tau));
          h_max = std::max(h_max, min_snap_shape::d2(tau));
        }
      }
      double hd_min = std::min(min_snap_shape::d3(tau_a), min_snap_shape::d3(tau_b));
      double hd_max = std::max(min_snap_shape::d3(tau_a), min_snap_shape::d3(tau_b));
      for (double tau : kJerkPeakTau) {
        if (tau > tau_a && tau < tau_b) {
          hd_min = std::min(hd_min, min_snap_shape::d3(tau));
          hd_max = std::max(hd_max, min_snap_shape::d3(tau));
        }
      }
      h_min *= h_scale;
      h_max *= h_scale;
      hd_min *= j_scale;
      hd_max *= j_scale;
      const double h_hi = std::max(std::abs(h_min), std::abs(h_max));
      const double h_lo = (h_min > 0.0) ? h_min : (h_max < 0.0 ? -h_max : 0.0);
      const double j_hi = std::max(std::abs(hd_min), std::abs(hd_max));
      const double wa = z_(s.ta).ddz + g;
      // Linear in t within the phase (w' = the phase's jerk).
      const double wb = wa + w_dot * (s.tb - s.ta);
      const double w_lo = std::min(wa, wb), w_hi = std::max(wa, wb);
      // J = h' w - h w' by interval arithmetic (w > 0; w' fixed).
      const double J_lo = std::min(hd_min * w_lo, hd_min * w_hi) + std::min(-h_min * w_dot, -h_max * w_dot);
      const double J_hi = std::max(hd_max * w_lo, hd_max * w_hi) + std::max(-h_min * w_dot, -h_max * w_dot);
      const double J_abs = std::max(std::abs(J_lo), std::abs(J_hi));
      const double thrust_hi2 = h_hi * h_hi + w_hi * w_hi;
      const double thrust_lo2 = h_lo * h_lo + w_lo * w_lo;  // N^2 >= this
      const double n_lo = std::sqrt(thrust_lo2);
      const double m_lo = std::sqrt(h_lo * h_lo * dir_c_ * dir_c_ + w_lo * w_lo);
      // |d/dt (f/|f|)| = |J| / N^2 <= |nu| / |f|.
      const double tilt_rate_hi =
          std::min(J_abs / thrust_lo2, std::sqrt((j_hi * j_hi + w_dot * w_dot) / thrust_lo2));
      // Per axis from the closed forms above; each also bounded through the tilt rate.
      const double omega_x_hi = std::min(std::abs(dir_s_) * w_hi * J_abs / (thrust_lo2 * m_lo), tilt_rate_hi);
      const double omega_y_hi = std::min(std::abs(dir_c_) * J_abs / (n_lo * m_lo), tilt_rate_hi);
      const double omega_z_hi = std::min(h_hi * std::abs(dir_s_ * dir_c_) * J_abs / (n_lo * m_lo * m_lo),
                                         tilt_rate_hi * h_hi / w_lo);
      const double rate_hi = std::max({omega_x_hi, omega_y_hi, omega_z_hi});
      if (thrust_hi2 <= thrust_max2 && thrust_lo2 >= thrust_min2 && rate_hi <= rate_max) continue;

      const double tm = 0.5 * (s.ta + s.tb);
      const PointInputs mid = xy_phase_inputs(tm);
      if (violates(mid)) {
        found_t = tm;
        break;
      }
      if (s.tb - s.ta <= kMinSection_s || top + 2 > static_cast<int>(stack.size())) {
        const PointInputs pa = xy_phase_inputs(s.ta);
        const PointInputs pb = xy_phase_inputs(s.tb);
        if (violates(pa) || violates(pb)) {
          found_t = violates(pa) ? s.ta : s.tb;
          break;
        }
        verdict.certified = false;
        continue;
      }
      stack[top++] = Section{tm, s.tb};
      stack[top++] = Section{s.ta, tm};
    }
  }
  if (!(low || high || found_t >= 0.0)) return verdict;

  // Infeasible: locate the worst value of every limit. Before the xy start analytically, the xy
  // phase by an exact scan every 1 ms plus the phase boundaries and the min-snap extremes.
  verdict.certified = true;
  double thrust_hi = rest_hi, thrust_hi_t = rest_hi_t;
  double thrust_lo = rest_lo, thrust_lo_t = rest_lo_t;
  double rate_hi = 0.0, rate_hi_t = 0.0;
  int rate_axis = 1;
  auto consider = [&](double t) {
    const PointInputs p = xy_phase_inputs(t);
    if (p.thrust_mps2 > thrust_hi) thrust_hi = p.thrust_mps2, thrust_hi_t = t;
    if (p.thrust_mps2 < thrust_lo) thrust_lo = p.thrust_mps2, thrust_lo_t = t;
    if (p.rate_radps > rate_hi) rate_hi = p.rate_radps, rate_hi_t = t, rate_axis = p.axis;
  };
  const int steps = static_cast<int>(std::ceil(T / kScanStep_s));
  for (int i = 0; i <= steps; ++i) consider(std::min(t3 + i * kScanStep_s, tz[5]));
  for (const double t : tz)
    if (t >= t3) consider(t);
  for (double tau : kAccelPeakTau) consider(t3 + tau * T);
  for (double tau : kJerkPeakTau) consider(t3 + tau * T);
  if (found_t >= 0.0) consider(found_t);  // the scan's grid may step over it

  if (thrust_hi > limits.a_q_max_mps2) {
    verdict.thrust_high = {true, thrust_hi_t, thrust_hi, limits.a_q_max_mps2, -1};
  }
  if (thrust_lo < limits.a_q_min_mps2) {
    verdict.thrust_low = {true, thrust_lo_t, thrust_lo, limits.a_q_min_mps2, -1};
  }
  if (rate_hi > rate_max) verdict.rates = {true, rate_hi_t, rate_hi, rate_max, rate_axis};
  if (verdict.thrust_high.violated) {
    verdict.reason = Feasibility::thrust_too_high;
  } else if (verdict.thrust_low.violated) {
    verdict.reason = Feasibility::thrust_too_low;
  } else {
    verdict.reason = Feasibility::rates_too_high;
  }
  return verdict;
}

}  // namespace gs::planning
