// The catch manoeuvre of the paper's Section V: a minimum-snap correction in x and y (eqs.
// (43)-(45)) flown during the high-thrust phase of a five-phase minimax-acceleration manoeuvre in z
// (Fig. 6, eqs. (48), (49)), its nominal inputs (eqs. (46), (47), (4), (5)) and a fast feasibility
// check against the input limits (eqs. (1), (2)).
//
// Time convention. t = 0 is the start of the z manoeuvre (hover at z0, eq. (49)); the vehicle is at
// rest at the catch point at t = T_z (eq. (48)), the nominal impact. The xy correction runs over
// the last T_xy of it, [T_z - T_xy, T_z] = [t3, t5] in the paper's Fig. 6. Before 0 the reference
// is the hover at (x0, y0, z0); after T_z it is the rest at (xT, yT, zT).
//
// The z manoeuvre. The acceleration profile of Fig. 6 has five intervals of constant jerk
//   [t0,t1]: -k_max   (0 -> -a_max)        [t1,t2]: 0   (-a_max, held for T_xy - a_max/k_max)
//   [t2,t3]: +k_max   (-a_max -> +a_max)   [t3,t4]: 0   (+a_max, held for T_xy - a_max/k_max)
//   [t4,t5]: -k_max   (+a_max -> 0)
// With the acceleration saturated at -a_max and +a_max (the minimax shape of Fig. 6) and [t3,t5]
// of length T_xy, this profile reproduces (48) and (49): zero end velocity forces equal hold times
// h, the length of [t3,t5] is h + a_max/k_max = T_xy, so T_z = 4 a_max/k_max + 2h
// = 2(a_max/k_max + T_xy) (48); the acceleration is odd about T_z/2, so
// z0 - zT = 2 int_{T_z/2}^{T_z} (t - T_z/2) z''(t) dt = a_max^2 T_xy / k_max + a_max T_xy^2 (49).
// It needs T_xy >= a_max/k_max. Jerk here takes the values -k_max, 0, +k_max, 0, -k_max (the two
// holds are the saturated acceleration of the minimax solution). a_max = 0 gives the
// constant-height correction (Fig. 7, dashed).
//
// Beyond the paper: the xy correction may start xy_lead_s before t3, so that it runs over the
// last T_xy + lead of the z manoeuvre (into the dive, whose thrust g - a_max must then stay
// positive) while the z manoeuvre, and so the height the catcher waits at, stays (48), (49). A
// longer correction needs less acceleration and jerk for the same distance; a radio outage that
// freezes the vehicle's attitude in it then costs less (docs/failsafe.md).
#pragma once

#include <Eigen/Core>
#include <array>
#include <optional>
#include <string_view>

#include "pa/constants.hpp"

namespace gs::planning {

// Input limits of eqs. (1) and (2): a_q,min <= a_q <= a_q,max and |Omega_i| <= Omega_max.
struct InputLimits {
  double a_q_min_mps2 = 1.0;
  double a_q_max_mps2 = 20.0;
  double omega_max_radps = 10.0;
};

struct CatchTrajectoryParams {
  Eigen::Vector2d start_xy_m = Eigen::Vector2d::Zero();   // (x0, y0), at rest
  Eigen::Vector2d target_xy_m = Eigen::Vector2d::Zero();  // (xT, yT), at rest at the impact
  double catch_height_m = 0.0;                            // zT (vehicle centre of gravity)
  double t_xy_s = 0.65;                                   // T_xy, length of [t3, t5] (Section V)
  double xy_lead_s = 0.0;                                 // the xy correction starts this long before t3
  double a_max_mps2 = 4.19;                               // Fig. 7
  double k_max_mps3 = 18.0;                               // Fig. 7
  double yaw_rad = 0.0;                                   // constant yaw psi for (47)
  double gravity_mps2 = pa::kGravity_mps2;
};

enum class CatchParamError {
  none,
  non_finite,
  non_positive_duration,  // T_xy <= 0
  negative_accel,         // a_max < 0
  non_positive_jerk,      // k_max <= 0
  non_positive_gravity,
  hold_too_short,  // T_xy < a_max / k_max: no hold phase, (48)/(49) cannot both hold
  bad_lead,        // xy_lead_s < 0, beyond t3, or with a_max >= g (no lift in the dive)
};
std::string_view to_string(CatchParamError error);
CatchParamError validate(const CatchTrajectoryParams& params);

// Closed-form minimum-snap motion from rest to rest, eqs. (43)-(45): with tau = t/T,
//   q(t) = q0 + (qT - q0) sigma(tau),  sigma = 35 tau^4 - 84 tau^5 + 70 tau^6 - 20 tau^7,
// whose fourth derivative is exactly (45). The Euler-Lagrange condition of (44) is q^(8) = 0, so
// the optimum is the degree-7 polynomial meeting the eight boundary conditions
// (q, q', q'', q''') = (q0, 0, 0, 0) at 0 and (qT, 0, 0, 0) at T.
struct MinSnapSample {
  double q = 0, dq = 0, ddq = 0, jerk = 0, snap = 0;
};
struct MinSnapAxis {
  double q0 = 0, qT = 0, duration_s = 1;
  // The polynomial on the closed interval [0, T] (so the snap at 0 and T is (45)'s, not zero);
  // outside it, at rest at the nearer end.
  MinSnapSample operator()(double t_s) const;
};

// The normalised shape sigma(tau) and its derivatives, with the points where they peak; the
// feasibility check uses them as exact candidate extremes.
namespace min_snap_shape {
double sigma(double tau);
double d1(double tau);  // 140 tau^3 (1 - tau)^3
double d2(double tau);  // 420 tau^2 (1 - tau)^2 (1 - 2 tau)
double d3(double tau);  // 840 tau (1 - tau) (5 tau^2 - 5 tau + 1)
double d4(double tau);  // 840 (1 - 12 tau + 30 tau^2 - 20 tau^3), the bracket of (45)
}  // namespace min_snap_shape

// The z manoeuvre (Fig. 6) as five constant-jerk phases; see the file comment.
struct ZSample {
  double z = 0, dz = 0, ddz = 0, jerk = 0;
};
class MinimaxZManoeuvre {
 public:
  MinimaxZManoeuvre() = default;
  MinimaxZManoeuvre(double z_T_m, double t_xy_s, double a_max_mps2, double k_max_mps3);
  // The phases on [0, T_z] (a boundary belongs to the later phase, T_z to the last); hover at z0
  // before, rest at zT after.
  ZSample operator()(double t_s) const;
  double duration_s() const { return t_[5]; }      // T_z, eq. (48)
  double start_height_m() const { return z_[0]; }  // z0, eq. (49)
  double end_height_m() const { return z_end_; }
  // Phase boundaries t0 = 0 .. t5 = T_z and the jerk of each of the five phases.
  const std::array<double, 6>& phase_times_s() const { return t_; }
  const std::array<double, 5>& phase_jerks_mps3() const { return jerk_; }

 private:
  std::array<double, 6> t_{};
  std::array<double, 5> jerk_{}, z_{}, v_{}, a_{};
  double z_end_ = 0;
};

// The nominal state and inputs at one instant.
struct CatchReference {
  double t_s = 0;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_mps = Eigen::Vector3d::Zero();
  Eigen::Vector3d acceleration_mps2 = Eigen::Vector3d::Zero();
  Eigen::Vector3d jerk_mps3 = Eigen::Vector3d::Zero();
  double roll_rad = 0, pitch_rad = 0, yaw_rad = 0;             // from (4): thrust along f
  double thrust_mps2 = 0;                                      // a_q = |f|, (46)
  Eigen::Vector3d body_rates_radps = Eigen::Vector3d::Zero();  // Omega, (47) and psi' = 0
};

// Nominal inputs of a flat-output trajectory for a constant yaw (eqs. (46), (47), (4), (5)).
// f = a + (0, 0, g); a_q = |f|; roll and pitch put the body z-axis along f (eq. (4) with
// B_I R = R_x(phi) R_y(theta) R_z(psi), eq. (3)); (Omega_y, -Omega_x, 0) = B_I R (d/dt)(f/|f|)
// (47); and Omega_z = -tan(phi) Omega_y, the body yaw rate that keeps psi' = 0 in (5) (docs/paper-notes.md:
// (47) is for a constant yaw and does not fix Omega_z).
struct NominalInputs {
  double thrust_mps2 = 0;
  Eigen::Vector3d body_rates_radps = Eigen::Vector3d::Zero();
  double roll_rad = 0, pitch_rad = 0;
};
NominalInputs nominal_inputs(const Eigen::Vector3d& acceleration_mps2, const Eigen::Vector3d& jerk_mps3,
                             double yaw_rad, double gravity_mps2 = pa::kGravity_mps2);

enum class Feasibility { feasible, thrust_too_high, thrust_too_low, rates_too_high };
std::string_view to_string(Feasibility verdict);

struct LimitViolation {
  bool violated = false;
  double t_s = 0;    // time of the worst violation (trajectory time)
  double value = 0;  // a_q (m/s^2) or the largest |Omega_i| (rad/s) there
  double limit = 0;
  int axis = -1;  // rates: 0, 1, 2 for Omega_x, Omega_y, Omega_z
};

// What check_feasibility guarantees (see catch_trajectory.cpp for the bounds):
// - Before the xy start (t3 - xy_lead_s; xy at rest): exact. The thrust is z'' + g, piecewise
//   linear, its extremes at the phase boundaries, and the body rates are zero (the jerk is
//   parallel to f).
// - The phases from the xy start to t5 (xy moving): recursive bisection. On each section rigorous upper
//   and lower bounds of a_q and of max_i |Omega_i| are formed from the exact ranges of the
//   min-snap acceleration and jerk (their extremes are at known tau) and of z'' + g (linear). A
//   section whose bounds satisfy the limits is certified; one whose exact midpoint value violates
//   them makes the trajectory infeasible; otherwise it is split, down to 1 ms. A 1 ms section
//   that is still undecided is accepted when its exact values at both ends and the midpoint are
//   within the limits, and the verdict is then marked certified = false (the limit is met within
//   the bound's slack over 1 ms; nothing sampled violates it).
// - So: feasible && certified means the limits hold at every instant of [0, T_z]; infeasible
//   means a limit is violated at a reported instant. When infeasible, each violated limit's
//   worst value is located by an exact scan every 1 ms plus the analytic candidate points.
// - The verdict's reason is by precedence thrust too high, thrust too low, rates too high; every
//   violated limit is reported in its own field.
struct FeasibilityVerdict {
  Feasibility reason = Feasibility::feasible;
  bool certified = true;
  LimitViolation thrust_high, thrust_low, rates;
  bool feasible() const { return reason == Feasibility::feasible; }
  const LimitViolation& primary() const;  // the violation named by reason (feasible: thrust_high)
};

class CatchTrajectory {
 public:
  // std::nullopt when validate(params) != CatchParamError::none.
  static std::optional<CatchTrajectory> create(const CatchTrajectoryParams& params);

  CatchReference reference(double t_s) const;
  FeasibilityVerdict check_feasibility(const InputLimits& limits) const;

  const CatchTrajectoryParams& params() const { return params_; }
  const MinimaxZManoeuvre& z_manoeuvre() const { return z_; }
  double duration_s() const { return z_.duration_s(); }  // T_z (impact time)
  double xy_duration_s() const { return params_.t_xy_s + params_.xy_lead_s; }
  double xy_start_time_s() const { return z_.duration_s() - xy_duration_s(); }  // t3 - lead
  double start_height_m() const { return z_.start_height_m(); }                 // z0

 private:
  explicit CatchTrajectory(const CatchTrajectoryParams& params);
  // Exact thrust and max |Omega_i| at t in the xy phase from the closed forms of (47).
  struct PointInputs {
    double thrust_mps2, rate_radps;
    int axis;
  };
  PointInputs xy_phase_inputs(double t_s) const;

  CatchTrajectoryParams params_;
  MinimaxZManoeuvre z_;
  MinSnapAxis x_, y_;
  double distance_m_ = 0;         // |(xT - x0, yT - y0)|
  double dir_c_ = 1, dir_s_ = 0;  // travel direction in the yaw frame R_z(psi) (cos, sin)
};

}  // namespace gs::planning
