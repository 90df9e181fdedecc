// A small truth world for the estimator tests, written independently of the ground station's
// models (groundstation/model) and of the estimator: its own rigid-body vehicles with thrust and
// rate lags, its own pole dynamics (angular momentum about the pivot or the centre, drag by a
// 100-segment midpoint rule instead of the model's closed form, the plate's rotation terms and
// drag included while the pole rests on a plate), its own launch (unilateral contact: the pole
// leaves when the plate would have to pull) and impact (plate crossing, angular momentum about
// the contact point conserved), controllers that fly the vehicles from the truth, and a motion
// capture with Gaussian noise. It uses only Eigen and the shared constants.
//
// Scenarios: a balanced hover on vehicle 1, and a throw from vehicle 1 onto vehicle 2. The throw
// (not the paper's optimal one): vehicle 1 balances the pole while accelerating upwards, then its
// pivot accelerates towards -x so that the pole turns towards +x, then it cuts the thrust to
// a_min; the pole leaves when the plate would have to pull (F_N < 0), tens of milliseconds into
// the thrust decay, rotating at about 3 rad/s, and lands after about 0.8 s on vehicle 2, which
// waits with its plate where the truth pole's lower end crosses the catching height.
#pragma once

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <random>
#include <vector>

#include "pa/constants.hpp"

namespace estimation_test {

using Eigen::Matrix3d;
using Eigen::Quaterniond;
using Eigen::Vector3d;

struct WorldParams {
  double step_s = 5e-4;
  int steps_per_frame = 10;  // 200 Hz motion capture
  double gravity = pa::kGravity_mps2;
  double thrust_tau_s = 0.03;  // motors (the airframe's figure, firmware config)
  double rate_tau_s = 0.012;   // on-board rate loop
  double a_min = 1.0;
  double a_max = 20.0;
  double plate_height_m = pa::kPlateHeightAboveCg_m;
  double plate_radius_m = 0.5 * pa::kPlateDiameter_m;
  double pole_half_length_m = pa::kPoleHalfLength_m;
  double pole_mass_kg = pa::kPoleMass_kg;
  double c_axial = pa::kPoleDragAxial;
  double c_normal = pa::kPoleDragNormal;
  double c_rot = pa::kPoleDragRotational;
  int drag_segments = 100;
  double sigma_position_m = 1e-3;
  double sigma_rotation_rad = 1e-3;
};

enum class TruthMode { free, on_vehicle1, on_vehicle2 };

struct Pose {
  Vector3d p = Vector3d::Zero();
  Quaterniond q = Quaterniond::Identity();
};

struct Command {
  double thrust_mps2 = pa::kGravity_mps2;
  Vector3d rates_radps = Vector3d::Zero();
};

// The pole in free-flight coordinates: centre, velocity, body z-axis, angular rate (normal to it).
struct PoleTruth {
  TruthMode mode = TruthMode::on_vehicle1;
  Vector3d p = Vector3d::Zero();
  Vector3d v = Vector3d::Zero();
  Vector3d n = Vector3d::UnitZ();
  Vector3d omega = Vector3d::Zero();
  double normal_force_per_mass = 0.0;  // on a plate
};

struct Frame {
  double t_s = 0.0;
  std::array<Pose, 2> vehicle;     // noisy
  Pose pole;                       // noisy
  std::array<Command, 2> command;  // computed at t_s from the truth, acting until the next frame
  PoleTruth truth;
  std::array<Vector3d, 2> vehicle_p;  // truth
  std::array<Vector3d, 2> vehicle_v;
};

struct Crossing {
  double t_s = 0.0;
  double x = 0.0;
  double y = 0.0;
};

class World {
 public:
  struct Vehicle {
    Vector3d p = Vector3d::Zero();
    Vector3d v = Vector3d::Zero();
    Matrix3d r = Matrix3d::Identity();  // inertial from body
    double thrust = pa::kGravity_mps2;
    Vector3d rates = Vector3d::Zero();
    Command cmd;
  };

  World(const WorldParams& params, unsigned seed) : wp_(params), rng_(seed) {}

  const WorldParams& params() const { return wp_; }
  double time() const { return t_; }
  Vehicle& vehicle(int i) { return veh_[i]; }
  const Vehicle& vehicle(int i) const { return veh_[i]; }

  // The pole resting on vehicle i's plate centre, direction n_pivot (pivot to centre), at rest
  // relative to it; body_sign: the pole's body z-axis is body_sign * n_pivot.
  void place_pole_on(int i, const Vector3d& n_pivot, double body_sign) {
    mode_ = i == 0 ? TruthMode::on_vehicle1 : TruthMode::on_vehicle2;
    contact_body_ = Vector3d(0.0, 0.0, wp_.plate_height_m);
    np_ = n_pivot.normalized();
    w_.setZero();
    sign_ = body_sign;
  }

  // The pole in free flight (body z-axis n, rate omega normal to it).
  void place_pole_free(const Vector3d& p, const Vector3d& v, const Vector3d& n, const Vector3d& omega) {
    mode_ = TruthMode::free;
    pp_ = p;
    pv_ = v;
    np_ = n.normalized();
    w_ = omega - omega.dot(np_) * np_;
  }

  TruthMode mode() const { return mode_; }
  std::optional<double> launch_time() const { return launch_t_; }
  std::optional<double> impact_time() const { return impact_t_; }
  int impact_vehicle() const { return impact_vehicle_; }  // 0 or 1
  std::optional<Crossing> crossing() const { return crossing_; }
  void set_catch_height(double z) { catch_height_ = z; }

  // The pivot-to-centre direction and rate while on a plate (for the controllers).
  Vector3d pivot_direction() const { return np_; }
  Vector3d pole_rate() const { return w_; }

  PoleTruth pole_truth() const {
    PoleTruth t;
    t.mode = mode_;
    if (mode_ == TruthMode::free) {
      t.p = pp_;
      t.v = pv_;
      t.n = np_;
      t.omega = w_;
    } else {
      const Vehicle& v = veh_[mode_ == TruthMode::on_vehicle1 ? 0 : 1];
      const Vector3d arm = v.r * contact_body_;
      const Vector3d pivot = v.p + arm;
      const Vector3d pivot_v = v.v + (v.r * v.rates).cross(arm);
      const double l = wp_.pole_half_length_m;
      t.p = pivot + l * np_;
      t.v = pivot_v + l * w_.cross(np_);
      t.n = sign_ * np_;
      t.omega = w_;
      t.normal_force_per_mass = last_fn_;
    }
    return t;
  }

  // Advances one step with the vehicles' current commands.
  void step() {
    const double h = wp_.step_s;
    std::array<Vector3d, 2> acc0;
    std::array<Vector3d, 2> rate_dot0;
    std::array<Vehicle, 2> before = veh_;
    for (int i = 0; i < 2; ++i) {
      acc0[i] = vehicle_acceleration(veh_[i]);
      rate_dot0[i] = (veh_[i].cmd.rates_radps - veh_[i].rates) / wp_.rate_tau_s;
      integrate_vehicle(veh_[i], h);
    }
    if (mode_ == TruthMode::free) {
      step_free(h, before);
    } else {
      const int i = mode_ == TruthMode::on_vehicle1 ? 0 : 1;
      step_on_plate(h, before[i], acc0[i], rate_dot0[i]);
    }
    t_ += h;
  }

  // Motion-capture frame at the current time (noise from the world's generator).
  Frame frame() {
    Frame f;
    f.t_s = t_;
    for (int i = 0; i < 2; ++i) {
      f.vehicle[i] = noisy(veh_[i].p, Quaterniond(veh_[i].r));
      f.command[i] = veh_[i].cmd;
      f.vehicle_p[i] = veh_[i].p;
      f.vehicle_v[i] = veh_[i].v;
    }
    f.truth = pole_truth();
    f.pole = noisy(f.truth.p, Quaterniond::FromTwoVectors(Vector3d::UnitZ(), f.truth.n));
    return f;
  }

  // Drag loads of the paper's law (10)-(15) by the midpoint rule: force, torque about the centre.
  void drag_loads(const Vector3d& v, const Vector3d& n, const Vector3d& w, Vector3d& force,
                  Vector3d& torque) const {
    const int k_max = wp_.drag_segments;
    const double l = wp_.pole_half_length_m;
    const double dxi = 2.0 * l / k_max;
    force.setZero();
    torque.setZero();
    const Vector3d wn = w.cross(n);
    for (int k = 0; k < k_max; ++k) {
      const double xi = -l + (k + 0.5) * dxi;
      const Vector3d vel = v + xi * wn;
      const Vector3d vz = vel.dot(n) * n;
      const Vector3d vxy = vel - vz;
      force += (-wp_.c_axial * vz.norm() * vz - wp_.c_normal * vxy.norm() * vxy) * dxi;
      torque += -wp_.c_rot * (xi * n).cross(vel.norm() * vel) * dxi;
    }
  }

  Vector3d vehicle_acceleration(const Vehicle& v) const {
    return v.r.col(2) * v.thrust - Vector3d(0.0, 0.0, wp_.gravity);
  }

 private:
  static Matrix3d exp_so3(const Vector3d& phi) {
    const double a = phi.norm();
    if (a < 1e-12) return Matrix3d::Identity();
    return Eigen::AngleAxisd(a, phi / a).toRotationMatrix();
  }

  void integrate_vehicle(Vehicle& v, double h) const {
    const Vector3d acc0 = vehicle_acceleration(v);
    const double thrust0 = v.thrust;
    const Vector3d rates0 = v.rates;
    const double dt = std::exp(-h / wp_.thrust_tau_s);
    const double dr = std::exp(-h / wp_.rate_tau_s);
    v.thrust = v.cmd.thrust_mps2 + (thrust0 - v.cmd.thrust_mps2) * dt;
    v.rates = v.cmd.rates_radps + (rates0 - v.cmd.rates_radps) * dr;
    v.r = v.r * exp_so3(0.5 * (rates0 + v.rates) * h);
    const Vector3d acc1 = vehicle_acceleration(v);
    v.p += v.v * h + (h * h / 6.0) * (2.0 * acc0 + acc1);
    v.v += 0.5 * h * (acc0 + acc1);
  }

  // ---- free flight: (p, v, n, omega) with omega' = M_perp / Theta ----
  struct FreeState {
    Vector3d p, v, n, w;
  };
  FreeState free_rate(const FreeState& s) const {
    Vector3d force;
    Vector3d torque;
    drag_loads(s.v, s.n, s.w, force, torque);
    const double m = wp_.pole_mass_kg;
    const double theta = m * wp_.pole_half_length_m * wp_.pole_half_length_m / 3.0;
    FreeState d;
    d.p = s.v;
    d.v = force / m - Vector3d(0.0, 0.0, wp_.gravity);
    d.n = s.w.cross(s.n);
    d.w = (torque - torque.dot(s.n) * s.n) / theta;
    return d;
  }
  FreeState free_step(const FreeState& s, double h) const {
    const auto add = [](const FreeState& a, const FreeState& b, double k) {
      return FreeState{a.p + k * b.p, a.v + k * b.v, a.n + k * b.n, a.w + k * b.w};
    };
    const FreeState k1 = free_rate(s);
    const FreeState k2 = free_rate(add(s, k1, 0.5 * h));
    const FreeState k3 = free_rate(add(s, k2, 0.5 * h));
    const FreeState k4 = free_rate(add(s, k3, h));
    FreeState out{s.p + h / 6.0 * (k1.p + 2 * k2.p + 2 * k3.p + k4.p),
                  s.v + h / 6.0 * (k1.v + 2 * k2.v + 2 * k3.v + k4.v),
                  s.n + h / 6.0 * (k1.n + 2 * k2.n + 2 * k3.n + k4.n),
                  s.w + h / 6.0 * (k1.w + 2 * k2.w + 2 * k3.w + k4.w)};
    out.n.normalize();
    out.w -= out.w.dot(out.n) * out.n;
    return out;
  }

  // Lower end relative to vehicle i's plate: height along the normal and radial distance.
  void plate_relation(const FreeState& s, const Vehicle& v, double& height, double& radial) const {
    const double sgn = s.n.z() >= 0.0 ? 1.0 : -1.0;
    const Vector3d end = s.p - wp_.pole_half_length_m * sgn * s.n;
    const Vector3d rel = v.r.transpose() * (end - v.p) - Vector3d(0.0, 0.0, wp_.plate_height_m);
    height = rel.z();
    radial = rel.head<2>().norm();
  }

  double lower_end_height(const FreeState& s) const {
    return s.p.z() - wp_.pole_half_length_m * std::abs(s.n.z());
  }

  void step_free(double h, const std::array<Vehicle, 2>& before) {
    const FreeState s0{pp_, pv_, np_, w_};
    FreeState s1 = free_step(s0, h);
    // Crossing of the catching height (downwards), for the catch-point truth.
    if (catch_height_ && !crossing_) {
      const double z0 = lower_end_height(s0) - *catch_height_;
      const double z1 = lower_end_height(s1) - *catch_height_;
      if (z0 > 0.0 && z1 <= 0.0) {
        const double frac = z0 / (z0 - z1);
        const FreeState sc = free_step(s0, frac * h);
        const double sgn = sc.n.z() >= 0.0 ? 1.0 : -1.0;
        const Vector3d end = sc.p - wp_.pole_half_length_m * sgn * sc.n;
        crossing_ = Crossing{t_ + frac * h, end.x(), end.y()};
      }
    }
    for (int i = 0; i < 2; ++i) {
      double h0 = 0.0, r0 = 0.0, h1 = 0.0, r1 = 0.0;
      plate_relation(s0, before[i], h0, r0);
      plate_relation(s1, veh_[i], h1, r1);
      if (!(h0 > 0.0 && h1 <= 0.0) || r1 > wp_.plate_radius_m) continue;
      // Impact at the crossing: sub-step there, then conserve the angular momentum about the
      // contact point (moving with the plate).
      const double frac = h0 / (h0 - h1);
      const FreeState sc = free_step(s0, frac * h);
      const Vehicle& v = veh_[i];
      const double sgn = sc.n.z() >= 0.0 ? 1.0 : -1.0;
      const Vector3d n_pivot = sgn * sc.n;
      const double l = wp_.pole_half_length_m;
      const double m = wp_.pole_mass_kg;
      const Vector3d end = sc.p - l * n_pivot;
      contact_body_ = v.r.transpose() * (end - v.p);
      const Vector3d contact_v = v.v + (v.r * v.rates).cross(v.r * contact_body_);
      const double theta = m * l * l / 3.0;
      Vector3d h_c = theta * sc.w + m * (l * n_pivot).cross(sc.v - contact_v);
      h_c -= h_c.dot(n_pivot) * n_pivot;
      w_ = h_c / (4.0 * m * l * l / 3.0);
      np_ = n_pivot;
      sign_ = sgn;
      mode_ = i == 0 ? TruthMode::on_vehicle1 : TruthMode::on_vehicle2;
      if (!impact_t_) {
        impact_t_ = t_ + frac * h;
        impact_vehicle_ = i;
      }
      // The rest of the step on the plate.
      step_on_plate((1.0 - frac) * h, veh_[i], vehicle_acceleration(veh_[i]),
                    (veh_[i].cmd.rates_radps - veh_[i].rates) / wp_.rate_tau_s);
      return;
    }
    pp_ = s1.p;
    pv_ = s1.v;
    np_ = s1.n;
    w_ = s1.w;
  }

  // ---- on a plate: (n, omega) about the pivot, I_p omega' = torque about the pivot ----
  struct PlateState {
    Vector3d n, w;
  };
  PlateState plate_rate(const PlateState& s, const Vector3d& pivot_acc, const Vector3d& pivot_v,
                        Vector3d* contact_force) const {
    const double l = wp_.pole_half_length_m;
    const double m = wp_.pole_mass_kg;
    const Vector3d centre_v = pivot_v + l * s.w.cross(s.n);
    Vector3d force;
    Vector3d torque;
    drag_loads(centre_v, s.n, s.w, force, torque);
    const Vector3d f = pivot_acc + Vector3d(0.0, 0.0, wp_.gravity);
    Vector3d tau = (l * s.n).cross(-m * f + force) + torque;
    tau -= tau.dot(s.n) * s.n;
    PlateState d;
    d.n = s.w.cross(s.n);
    d.w = tau / (4.0 * m * l * l / 3.0);
    if (contact_force != nullptr) {
      const Vector3d centre_acc = pivot_acc + l * (d.w.cross(s.n) + s.w.cross(s.w.cross(s.n)));
      *contact_force = m * (centre_acc + Vector3d(0.0, 0.0, wp_.gravity)) - force;
    }
    return d;
  }

  void step_on_plate(double h, const Vehicle& v0, const Vector3d& acc0, const Vector3d& rate_dot0) {
    // Pivot motion: p_q + R c, its velocity and acceleration with the rotation terms.
    const Vector3d arm = v0.r * contact_body_;
    const Vector3d w_i = v0.r * v0.rates;
    const Vector3d pivot_v = v0.v + w_i.cross(arm);
    const Vector3d pivot_acc = acc0 + (v0.r * rate_dot0).cross(arm) + w_i.cross(w_i.cross(arm));
    const PlateState s0{np_, w_};
    Vector3d contact;
    const auto add = [](const PlateState& a, const PlateState& b, double k) {
      return PlateState{a.n + k * b.n, a.w + k * b.w};
    };
    const PlateState k1 = plate_rate(s0, pivot_acc, pivot_v, &contact);
    const PlateState k2 = plate_rate(add(s0, k1, 0.5 * h), pivot_acc, pivot_v, nullptr);
    const PlateState k3 = plate_rate(add(s0, k2, 0.5 * h), pivot_acc, pivot_v, nullptr);
    const PlateState k4 = plate_rate(add(s0, k3, h), pivot_acc, pivot_v, nullptr);
    const double fn = contact.dot(v0.r.col(2)) / wp_.pole_mass_kg;
    last_fn_ = fn;
    if (fn < 0.0 || np_.dot(v0.r.col(2)) < 0.1) {
      // Launch: the plate would have to pull. Free from here, with this step in free flight.
      const double l = wp_.pole_half_length_m;
      pp_ = v0.p + arm + l * np_;
      pv_ = pivot_v + l * w_.cross(np_);
      np_ = sign_ * np_;
      mode_ = TruthMode::free;
      if (!launch_t_) launch_t_ = t_;
      const FreeState s1 = free_step(FreeState{pp_, pv_, np_, w_}, h);
      pp_ = s1.p;
      pv_ = s1.v;
      np_ = s1.n;
      w_ = s1.w;
      return;
    }
    PlateState s1{s0.n + h / 6.0 * (k1.n + 2 * k2.n + 2 * k3.n + k4.n),
                  s0.w + h / 6.0 * (k1.w + 2 * k2.w + 2 * k3.w + k4.w)};
    s1.n.normalize();
    s1.w -= s1.w.dot(s1.n) * s1.n;
    np_ = s1.n;
    w_ = s1.w;
  }

  Pose noisy(const Vector3d& p, const Quaterniond& q) {
    std::normal_distribution<double> np(0.0, wp_.sigma_position_m);
    std::normal_distribution<double> nr(0.0, wp_.sigma_rotation_rad);
    Pose out;
    out.p = p + Vector3d(np(rng_), np(rng_), np(rng_));
    const Vector3d dr(nr(rng_), nr(rng_), nr(rng_));
    out.q = (q * Quaterniond(exp_so3(dr))).normalized();
    return out;
  }

  WorldParams wp_;
  std::mt19937_64 rng_;
  double t_ = 0.0;
  std::array<Vehicle, 2> veh_;
  TruthMode mode_ = TruthMode::on_vehicle1;
  Vector3d contact_body_ = Vector3d(0.0, 0.0, pa::kPlateHeightAboveCg_m);
  Vector3d np_ = Vector3d::UnitZ();  // on a plate: pivot to centre; free: the body z-axis
  Vector3d w_ = Vector3d::Zero();
  double sign_ = 1.0;               // body z-axis = sign * pivot direction
  Vector3d pp_ = Vector3d::Zero();  // free: centre
  Vector3d pv_ = Vector3d::Zero();
  double last_fn_ = 0.0;
  std::optional<double> launch_t_;
  std::optional<double> impact_t_;
  int impact_vehicle_ = -1;
  std::optional<double> catch_height_;
  std::optional<Crossing> crossing_;
};

// ---------------------------------------------------------------------------------------------
// The world's flight software (from the truth).

inline double wrap(double a) { return std::atan2(std::sin(a), std::cos(a)); }

// Thrust and body rates that track a desired acceleration with zero yaw.
inline Command track_acceleration(const World& w, const World::Vehicle& v, const Vector3d& acc) {
  const WorldParams& p = w.params();
  Vector3d t = acc + Vector3d(0.0, 0.0, p.gravity);
  t.z() = std::max(t.z(), 0.2 * p.gravity);
  const Vector3d b3 = v.r.col(2);
  const Vector3d b3_des = t.normalized();
  Command c;
  c.thrust_mps2 = std::clamp(t.dot(b3), p.a_min, p.a_max);
  const Vector3d e_body = v.r.transpose() * b3.cross(b3_des);
  constexpr double kAttitudeGain = 25.0;
  const double psi = std::atan2(v.r(1, 0), v.r(0, 0));
  c.rates_radps = Vector3d(kAttitudeGain * e_body.x(), kAttitudeGain * e_body.y(), -5.0 * wrap(psi));
  for (int k = 0; k < 3; ++k) c.rates_radps(k) = std::clamp(c.rates_radps(k), -10.0, 10.0);
  return c;
}

inline Command hold_position(const World& w, const World::Vehicle& v, const Vector3d& target) {
  const Vector3d acc = 4.0 * (target - v.p) - 4.0 * v.v;
  return track_acceleration(w, v, acc.cwiseMax(-8.0).cwiseMin(8.0));
}

// Balancing the pole (an inverted pendulum on the pivot, per horizontal axis): the pivot
// accelerates under the pole so that its tilt follows alpha_ref (x) and 0 (y), with an outer
// loop on the position (x_target used unless x_free) and a vertical acceleration feedforward.
struct BalanceReference {
  Vector3d target = Vector3d::Zero();
  double alpha_x = 0.0;
  double alpha_x_rate = 0.0;
  double z_acc_ff = 0.0;
  double z_vel_ref = 0.0;
  bool x_free = false;
  bool z_free = false;
};

inline Command balance(const World& w, const World::Vehicle& v, const BalanceReference& ref) {
  const WorldParams& p = w.params();
  const Vector3d n = w.pivot_direction();
  const Vector3d ndot = w.pole_rate().cross(n);
  const double l = p.pole_half_length_m;
  constexpr double kWn = 7.0;
  constexpr double kZeta = 1.0;
  constexpr double kPos = 0.8;
  const double g_eff = p.gravity + ref.z_acc_ff;
  Vector3d acc = Vector3d::Zero();
  for (int axis = 0; axis < 2; ++axis) {
    const double alpha = n(axis) / n.z();
    const double alpha_rate = ndot(axis);
    double alpha_ref = axis == 0 ? ref.alpha_x : 0.0;
    const double rate_ref = axis == 0 ? ref.alpha_x_rate : 0.0;
    if (!(axis == 0 && ref.x_free)) {
      alpha_ref += (kPos * kPos * (ref.target(axis) - v.p(axis)) - 2.0 * kPos * v.v(axis)) / g_eff;
    }
    // alpha'' = 3/(4L) (g alpha - x''): choose x'' so that alpha'' = -kWn^2 e - 2 zeta kWn e'.
    acc(axis) = g_eff * alpha + (4.0 * l / 3.0) * (kWn * kWn * (alpha - alpha_ref) +
                                                   2.0 * kZeta * kWn * (alpha_rate - rate_ref));
  }
  acc.z() = ref.z_free ? ref.z_acc_ff + 4.0 * (ref.z_vel_ref - v.v.z())
                       : 4.0 * (ref.target.z() - v.p.z()) - 4.0 * v.v.z();
  return track_acceleration(w, v, acc);
}

// ---------------------------------------------------------------------------------------------
// Scenarios

struct ThrowOptions {
  double balance_s = 1.0;    // balanced hover before the throw
  double up_acc_mps2 = 7.0;  // vertical acceleration of the throw
  double up_s = 0.6;
  double flick_s = 0.25;              // the last part of the throw: the pivot accelerates towards -x
  double flick_acc_mps2 = 9.5;        // so that the pole turns towards +x
  double cut_s = 0.3;                 // the thrower's minimum-thrust phase after the throw
  double catch_below_launch_m = 0.1;  // catching height below the lower end's launch height
  double after_impact_s = 0.3;
  bool with_catcher = true;            // vehicle 2 waits at the crossing (else it stays away)
  std::optional<Crossing> catcher_at;  // where vehicle 2 waits (from a run without it)
  std::optional<double> catch_height;
};

struct Recording {
  std::vector<Frame> frames;
  std::optional<double> launch_t;
  std::optional<double> impact_t;
  int impact_vehicle = -1;  // 0 or 1
  std::optional<Crossing> crossing;
  double catch_height = 0.0;
};

inline const Vector3d kVehicle1Start(0.0, 0.0, 1.0);
inline const Vector3d kVehicle2Away(2.5, 0.0, 1.0);

inline World make_world(const WorldParams& params, unsigned seed) {
  World w(params, seed);
  w.vehicle(0).p = kVehicle1Start;
  w.vehicle(1).p = kVehicle2Away;
  w.place_pole_on(0, Vector3d(0.02, -0.01, 1.0), 1.0);
  return w;
}

// A balanced hover on vehicle 1 (with a small lateral move), vehicle 2 hovering nearby.
inline Recording record_balanced_hover(const WorldParams& params, unsigned seed, double duration_s) {
  World w = make_world(params, seed);
  Recording rec;
  const int frames = static_cast<int>(std::lround(duration_s / (params.step_s * params.steps_per_frame)));
  for (int k = 0; k <= frames; ++k) {
    const double t = w.time();
    BalanceReference ref;
    ref.target = kVehicle1Start + Vector3d(t > 1.0 ? 0.3 : 0.0, t > 2.0 ? -0.2 : 0.0, 0.0);
    w.vehicle(0).cmd = balance(w, w.vehicle(0), ref);
    w.vehicle(1).cmd = hold_position(w, w.vehicle(1), kVehicle2Away);
    rec.frames.push_back(w.frame());
    for (int s = 0; s < params.steps_per_frame; ++s) w.step();
  }
  rec.launch_t = w.launch_time();
  return rec;
}

// The throw from vehicle 1 onto vehicle 2 (see ThrowOptions). Runs until after_impact_s past
// the impact (or 2.5 s past the launch).
inline Recording record_throw_run(const WorldParams& params, unsigned seed, const ThrowOptions& o) {
  World w = make_world(params, seed);
  Recording rec;
  Vector3d catcher_target = kVehicle2Away;
  if (o.with_catcher && o.catcher_at && o.catch_height) {
    catcher_target = Vector3d(o.catcher_at->x, o.catcher_at->y, *o.catch_height - params.plate_height_m);
    w.vehicle(1).p = catcher_target;
  }
  const double t_throw = o.balance_s;
  const double t_release = t_throw + o.up_s;
  double z_launch_end = 0.0;
  std::optional<Vector3d> thrower_home;
  for (int k = 0; k < 100000; ++k) {
    const double t = w.time();
    World::Vehicle& v1 = w.vehicle(0);
    if (t < t_throw) {
      BalanceReference ref;
      ref.target = kVehicle1Start;
      v1.cmd = balance(w, v1, ref);
    } else if (t < t_release && w.mode() == TruthMode::on_vehicle1) {
      BalanceReference ref;
      ref.target = kVehicle1Start;
      ref.z_free = true;
      ref.z_acc_ff = o.up_acc_mps2;
      ref.z_vel_ref = o.up_acc_mps2 * (t - t_throw);
      ref.x_free = true;
      v1.cmd = balance(w, v1, ref);
      if (t > t_release - o.flick_s) {
        const Vector3d acc(-o.flick_acc_mps2, 0.0,
                           o.up_acc_mps2 + 4.0 * (o.up_acc_mps2 * (t - t_throw) - v1.v.z()));
        v1.cmd = track_acceleration(w, v1, acc);
      }
    } else if (t < t_release + o.cut_s) {
      v1.cmd.thrust_mps2 = params.a_min;
      v1.cmd.rates_radps = Vector3d::Zero();
    } else {
      if (!thrower_home) thrower_home = v1.p + Vector3d(-0.6, 0.0, -0.3);
      v1.cmd = hold_position(w, v1, *thrower_home);
    }
    World::Vehicle& v2 = w.vehicle(1);
    if (w.mode() == TruthMode::on_vehicle2) {
      BalanceReference ref;
      ref.target = catcher_target;
      v2.cmd = balance(w, v2, ref);
    } else {
      v2.cmd = hold_position(w, v2, catcher_target);
    }
    rec.frames.push_back(w.frame());
    if (w.mode() == TruthMode::on_vehicle1 && t < t_release) {
      const PoleTruth pt = w.pole_truth();
      z_launch_end = pt.p.z() - params.pole_half_length_m * std::abs(pt.n.z());
    }
    if (w.launch_time() && !rec.launch_t) {
      rec.launch_t = w.launch_time();
      rec.catch_height = o.catch_height ? *o.catch_height : z_launch_end - o.catch_below_launch_m;
      w.set_catch_height(rec.catch_height);
    }
    if (w.impact_time() && t > *w.impact_time() + o.after_impact_s) break;
    if (rec.launch_t && t > *rec.launch_t + 2.5) break;
    for (int s = 0; s < params.steps_per_frame; ++s) w.step();
  }
  rec.impact_t = w.impact_time();
  rec.impact_vehicle = w.impact_vehicle();
  rec.crossing = w.crossing();
  return rec;
}

// The throw with the catcher in place: a first run without vehicle 2 finds the truth crossing of
// the catching height, the second places vehicle 2's plate there (the world is deterministic up
// to the motion-capture noise, which does not feed back into the truth).
inline Recording record_throw(const WorldParams& params, unsigned seed, ThrowOptions o = {}) {
  ThrowOptions first = o;
  first.with_catcher = false;
  const Recording probe = record_throw_run(params, seed, first);
  if (!probe.crossing) return probe;
  o.with_catcher = true;
  o.catcher_at = probe.crossing;
  o.catch_height = probe.catch_height;
  Recording rec = record_throw_run(params, seed, o);
  rec.catch_height = probe.catch_height;
  if (!rec.crossing) rec.crossing = probe.crossing;
  return rec;
}

}  // namespace estimation_test
