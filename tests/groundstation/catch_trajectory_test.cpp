// The catch manoeuvre of Section V: minimum snap (43)-(45) against independent numerical optima,
// the z manoeuvre against (48), (49) and Fig. 6, the nominal inputs (46), (47) flown through the
// vehicle model (4), (5), and the feasibility verdicts against brute-force scans.
#include "groundstation/planning/catch_trajectory.hpp"

#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <vector>

namespace {

using gs::planning::CatchTrajectory;
using gs::planning::CatchTrajectoryParams;
using gs::planning::Feasibility;
using gs::planning::InputLimits;
using gs::planning::MinimaxZManoeuvre;
using gs::planning::MinSnapAxis;

constexpr double kG = pa::kGravity_mps2;

CatchTrajectoryParams fig7_params() {
  CatchTrajectoryParams p;
  p.start_xy_m = {0.0, 0.0};
  p.target_xy_m = {0.25, 0.0};
  p.catch_height_m = 1.343;
  p.t_xy_s = 0.65;
  p.a_max_mps2 = 4.19;
  p.k_max_mps3 = 18.0;
  return p;
}

// Eq. (45) exactly as printed.
double snap_eq45(double t, double T, double x0, double xT) {
  return 840.0 / std::pow(T, 7) * (xT - x0) *
         (-20.0 * t * t * t + 30.0 * t * t * T - 12.0 * t * T * T + T * T * T);
}

// Brute force: worst a_q and max_i |Omega_i| of reference() on a fine grid.
struct Scan {
  double thrust_max = -1e300, thrust_min = 1e300, rate_max = 0.0;
};
Scan brute_force(const CatchTrajectory& traj, double step_s) {
  Scan s;
  for (double t = 0.0; t <= traj.duration_s() + 1e-12; t += step_s) {
    const auto r = traj.reference(t);
    // Phases before the xy motion: the signed vertical specific force (the check's convention).
    const double thrust = (t < traj.xy_start_time_s()) ? r.acceleration_mps2.z() + kG : r.thrust_mps2;
    s.thrust_max = std::max(s.thrust_max, thrust);
    s.thrust_min = std::min(s.thrust_min, thrust);
    s.rate_max = std::max(s.rate_max, r.body_rates_radps.cwiseAbs().maxCoeff());
  }
  return s;
}

}  // namespace

TEST_CASE("minimum snap meets the boundary conditions of (44) and its snap is (45)") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> pos(-3.0, 3.0), dur(0.2, 2.0);
  for (int trial = 0; trial < 20; ++trial) {
    const MinSnapAxis axis{pos(rng), pos(rng), dur(rng)};
    const double T = axis.duration_s;
    // Evaluate just inside the ends so that the polynomial, not the clamping, is tested.
    const auto a = axis(1e-300);
    const auto b = axis(T * (1.0 - 1e-15));
    CHECK(a.q == Approx(axis.q0).margin(1e-9));
    CHECK(std::abs(a.dq) < 1e-9);
    CHECK(std::abs(a.ddq) < 1e-9);
    CHECK(std::abs(a.jerk) < 1e-9);
    CHECK(b.q == Approx(axis.qT).margin(1e-9));
    CHECK(std::abs(b.dq) < 1e-9);
    CHECK(std::abs(b.ddq) < 1e-9);
    CHECK(std::abs(b.jerk) < 1e-9);
    for (double tau : {0.05, 0.3, 0.5, 0.77, 0.99}) {
      const double t = tau * T;
      CHECK(axis(t).snap == Approx(snap_eq45(t, T, axis.q0, axis.qT)).epsilon(1e-12).margin(1e-9));
    }
  }
  // The derivatives are consistent with each other (central differences of the position).
  const MinSnapAxis axis{-0.4, 1.1, 0.65};
  const double h = 1e-5;
  for (double t : {0.1, 0.3, 0.5}) {
    CHECK(axis(t).dq == Approx((axis(t + h).q - axis(t - h).q) / (2 * h)).epsilon(1e-8));
    CHECK(axis(t).ddq == Approx((axis(t + h).dq - axis(t - h).dq) / (2 * h)).epsilon(1e-8));
    CHECK(axis(t).jerk == Approx((axis(t + h).ddq - axis(t - h).ddq) / (2 * h)).epsilon(1e-8));
    CHECK(axis(t).snap == Approx((axis(t + h).jerk - axis(t - h).jerk) / (2 * h)).epsilon(1e-7));
  }
}

TEST_CASE("(45) is the optimum of the discretised minimum-snap problem (44)") {
  // Independent solution of (44): snap piecewise constant on N intervals, the quadruple
  // integrator (43) propagated exactly, the terminal state a linear function G u + free response,
  // and the minimum of sum u_i^2 dt subject to it the minimum-norm solution
  // u = G^T (G G^T)^-1 (s_T - s_free). No polynomial is assumed.
  const double T = 0.65, x0 = -0.2, xT = 0.45;
  const int N = 1000;
  const double dt = T / N;
  Eigen::MatrixXd G(4, N);
  for (int i = 0; i < N; ++i) {
    // A unit snap on [t_i, t_i + dt] and zero afterwards: its contribution at T to (q, q', q'',
    // q''') is the integral of (T - s)^k / k! over the interval, k = 3, 2, 1, 0.
    const double a = T - i * dt, b = T - (i + 1) * dt;
    G(0, i) = (std::pow(a, 4) - std::pow(b, 4)) / 24.0;
    G(1, i) = (std::pow(a, 3) - std::pow(b, 3)) / 6.0;
    G(2, i) = (std::pow(a, 2) - std::pow(b, 2)) / 2.0;
    G(3, i) = a - b;
  }
  const Eigen::Vector4d target(xT - x0, 0.0, 0.0, 0.0);  // from rest at x0
  const Eigen::VectorXd u = G.transpose() * (G * G.transpose()).ldlt().solve(target);
  double max_err = 0.0, max_u = 0.0;
  for (int i = 0; i < N; ++i) {
    const double t_mid = (i + 0.5) * dt;
    max_err = std::max(max_err, std::abs(u(i) - snap_eq45(t_mid, T, x0, xT)));
    max_u = std::max(max_u, std::abs(u(i)));
  }
  CHECK(max_err / max_u < 1e-4);
  // The closed form's cost (Simpson's rule on the N panels, O(dt^4): about 1e-12 relative here)
  // is below that of every piecewise-constant admissible snap, the discrete optimum included, and
  // the two agree as the discretisation refines.
  const MinSnapAxis axis{x0, xT, T};
  double cost_closed = 0.0;
  for (int i = 0; i < N; ++i) {
    const double a = axis(i * dt).snap, m = axis((i + 0.5) * dt).snap, b = axis((i + 1) * dt).snap;
    cost_closed += dt / 6.0 * (a * a + 4.0 * m * m + b * b);
  }
  const double cost_discrete = u.squaredNorm() * dt;
  CHECK(cost_closed <= cost_discrete);
  CHECK(cost_closed == Approx(cost_discrete).epsilon(1e-4));
}

TEST_CASE("(45) solves the Euler-Lagrange conditions of (44) for the same boundary conditions") {
  // q^(8) = 0: a degree-7 polynomial in t (monomial basis, not normalised) fixed by the eight
  // boundary conditions; solved numerically with Eigen.
  const double T = 0.8, x0 = 1.3, xT = -0.7;
  Eigen::Matrix<double, 8, 8> M = Eigen::Matrix<double, 8, 8>::Zero();
  auto deriv_row = [](double t, int k) {
    Eigen::Matrix<double, 1, 8> row = Eigen::Matrix<double, 1, 8>::Zero();
    for (int j = k; j < 8; ++j) {
      double c = 1.0;
      for (int m = 0; m < k; ++m) c *= (j - m);
      row(j) = c * std::pow(t, j - k);
    }
    return row;
  };
  for (int k = 0; k < 4; ++k) {
    M.row(k) = deriv_row(0.0, k);
    M.row(4 + k) = deriv_row(T, k);
  }
  Eigen::Matrix<double, 8, 1> rhs;
  rhs << x0, 0, 0, 0, xT, 0, 0, 0;
  const Eigen::Matrix<double, 8, 1> c = M.fullPivLu().solve(rhs);
  const MinSnapAxis axis{x0, xT, T};
  for (int k = 0; k <= 37; ++k) {
    const double t = k * T / 37;
    CHECK(axis(t).q == Approx(deriv_row(t, 0) * c).margin(1e-9));
    CHECK(axis(t).ddq == Approx(deriv_row(t, 2) * c).margin(1e-7));
    CHECK(axis(t).snap == Approx(deriv_row(t, 4) * c).margin(1e-5));
  }
}

TEST_CASE("the z manoeuvre satisfies (48) and (49) and has the phase structure of Fig. 6") {
  struct Case {
    double zT, txy, amax, kmax;
  };
  for (const Case& c : {Case{1.343, 0.65, 4.19, 18.0}, Case{0.5, 0.3, 2.0, 40.0}, Case{2.0, 1.2, 6.0, 10.0},
                        Case{1.0, 0.25, 4.5, 18.0}}) {
    const MinimaxZManoeuvre z(c.zT, c.txy, c.amax, c.kmax);
    CAPTURE(c.zT, c.txy, c.amax, c.kmax);
    CHECK(z.duration_s() == Approx(2.0 * (c.amax / c.kmax + c.txy)).epsilon(1e-14));  // (48)
    const double z0_eq49 = c.zT + (c.amax * c.amax * c.txy + c.amax * c.kmax * c.txy * c.txy) / c.kmax;
    CHECK(z.start_height_m() == Approx(z0_eq49).epsilon(1e-14));
    const auto& t = z.phase_times_s();
    const auto& j = z.phase_jerks_mps3();
    // Jerk -k, 0, +k, 0, -k; the high-thrust phase [t3, t5] lasts T_xy.
    CHECK(j[0] == -c.kmax);
    CHECK(j[1] == 0.0);
    CHECK(j[2] == c.kmax);
    CHECK(j[3] == 0.0);
    CHECK(j[4] == -c.kmax);
    CHECK(t[5] - t[3] == Approx(c.txy).epsilon(1e-14));
    for (int i = 0; i < 5; ++i) {
      if (t[i + 1] > t[i]) CHECK(z(0.5 * (t[i] + t[i + 1])).jerk == j[i]);  // holds may be empty
    }
    // The acceleration saturates at -a_max on [t1, t2] and at +a_max on [t3, t4].
    CHECK(z(0.5 * (t[1] + t[2])).ddz == Approx(-c.amax).epsilon(1e-12));
    CHECK(z(0.5 * (t[3] + t[4])).ddz == Approx(c.amax).epsilon(1e-12));

    // Independent integration of the jerk from hover at z0 of (49), exact over steps of at most
    // 10 us that end on the phase boundaries (the jerk is sampled inside each step): it must end
    // at rest at zT.
    double zz = z0_eq49, v = 0.0, a = 0.0;
    double max_dev = 0.0;
    for (int ph = 0; ph < 5; ++ph) {
      const int steps = static_cast<int>(std::ceil((t[ph + 1] - t[ph]) / 1e-5));
      const double hh = (t[ph + 1] - t[ph]) / std::max(steps, 1);
      for (int k = 0; k < steps; ++k) {
        const double jm = z(t[ph] + (k + 0.5) * hh).jerk;
        zz += v * hh + 0.5 * a * hh * hh + jm * hh * hh * hh / 6.0;
        v += a * hh + 0.5 * jm * hh * hh;
        a += jm * hh;
        max_dev = std::max(max_dev, std::abs(zz - z(t[ph] + (k + 1) * hh).z));
      }
    }
    CHECK(max_dev < 1e-9);
    CHECK(zz == Approx(c.zT).margin(1e-9));  // (49) lands at the catch height...
    CHECK(std::abs(v) < 1e-9);               // ...at rest (48)
    CHECK(std::abs(a) < 1e-9);
    // The closed form itself ends exactly there, and is continuous in z, z', z''.
    CHECK(z.end_height_m() == Approx(c.zT).margin(1e-12));
    for (int i = 1; i <= 5; ++i) {
      const auto before = z(t[i] - 1e-9);
      const auto after = z(t[i] + 1e-9);
      CHECK(before.ddz == Approx(after.ddz).margin(1e-6));
      CHECK(before.dz == Approx(after.dz).margin(1e-8));
      CHECK(before.z == Approx(after.z).margin(1e-8));
    }
  }
}

TEST_CASE("the catch trajectory starts hovering, moves xy during [t3, t5] and ends at rest") {
  const auto traj = CatchTrajectory::create(fig7_params());
  REQUIRE(traj);
  const auto start = traj->reference(0.0);
  CHECK(start.position_m.isApprox(Eigen::Vector3d(0.0, 0.0, traj->start_height_m())));
  CHECK(start.velocity_mps.norm() == 0.0);
  CHECK(start.thrust_mps2 == Approx(kG));
  const auto end = traj->reference(traj->duration_s());
  CHECK((end.position_m - Eigen::Vector3d(0.25, 0.0, 1.343)).norm() < 1e-9);
  CHECK(end.velocity_mps.norm() < 1e-9);
  CHECK(end.acceleration_mps2.norm() < 1e-9);
  CHECK(end.thrust_mps2 == Approx(kG).margin(1e-9));
  // No xy motion before t3; xy motion under high thrust (z'' >= 0) after.
  CHECK(traj->reference(traj->xy_start_time_s() - 1e-3).position_m.x() == 0.0);
  CHECK(traj->reference(traj->xy_start_time_s() + 0.1).position_m.x() > 0.0);
  for (double t = traj->xy_start_time_s(); t < traj->duration_s(); t += 0.01) {
    CHECK(traj->reference(t).acceleration_mps2.z() >= -1e-12);
  }
  CHECK(traj->xy_start_time_s() == Approx(traj->z_manoeuvre().phase_times_s()[3]));

  CatchTrajectoryParams bad = fig7_params();
  bad.t_xy_s = 0.2;  // < a_max / k_max = 0.233 s
  CHECK_FALSE(CatchTrajectory::create(bad));
  CHECK(gs::planning::validate(bad) == gs::planning::CatchParamError::hold_too_short);
  bad = fig7_params();
  bad.target_xy_m.x() = std::nan("");
  CHECK_FALSE(CatchTrajectory::create(bad));
}

TEST_CASE("a lead starts the xy correction in the dive: same z manoeuvre, gentler xy, same end") {
  CatchTrajectoryParams p = fig7_params();
  p.target_xy_m = {0.4, 0.0};  // a first catch's travel
  const auto paper = CatchTrajectory::create(p);
  p.xy_lead_s = 0.35;
  const auto led = CatchTrajectory::create(p);
  REQUIRE(paper);
  REQUIRE(led);
  // The z manoeuvre, and so the waiting height (49) and T_z (48), is the paper's.
  CHECK(led->duration_s() == paper->duration_s());
  CHECK(led->start_height_m() == paper->start_height_m());
  CHECK(led->xy_start_time_s() == Approx(paper->xy_start_time_s() - 0.35));
  CHECK(led->xy_start_time_s() < led->z_manoeuvre().phase_times_s()[3]);
  // At rest before its start, at the target at rest at T_z.
  CHECK(led->reference(led->xy_start_time_s() - 1e-3).position_m.x() == 0.0);
  const auto end = led->reference(led->duration_s());
  CHECK((end.position_m - Eigen::Vector3d(0.4, 0.0, 1.343)).norm() < 1e-9);
  CHECK(end.velocity_mps.norm() < 1e-9);
  // Peak horizontal acceleration and jerk fall as (T_xy / (T_xy + lead))^2 and ^3.
  double paper_acc = 0, led_acc = 0, paper_jerk = 0, led_jerk = 0;
  for (double t = 0.0; t <= paper->duration_s(); t += 1e-3) {
    paper_acc = std::max(paper_acc, std::abs(paper->reference(t).acceleration_mps2.x()));
    led_acc = std::max(led_acc, std::abs(led->reference(t).acceleration_mps2.x()));
    paper_jerk = std::max(paper_jerk, std::abs(paper->reference(t).jerk_mps3.x()));
    led_jerk = std::max(led_jerk, std::abs(led->reference(t).jerk_mps3.x()));
  }
  CHECK(led_acc == Approx(paper_acc * std::pow(0.65 / 1.0, 2)).epsilon(0.01));
  CHECK(led_jerk == Approx(paper_jerk * std::pow(0.65 / 1.0, 3)).epsilon(0.01));
  CHECK(led->check_feasibility(InputLimits{}).feasible());

  // Leads it cannot fly: negative, longer than the manoeuvre before t3, or into a dive without lift.
  CatchTrajectoryParams bad = p;
  bad.xy_lead_s = -0.1;
  CHECK(gs::planning::validate(bad) == gs::planning::CatchParamError::bad_lead);
  bad.xy_lead_s = led->z_manoeuvre().phase_times_s()[3] + 0.01;
  CHECK(gs::planning::validate(bad) == gs::planning::CatchParamError::bad_lead);
  bad = p;
  bad.a_max_mps2 = 10.0;
  bad.k_max_mps3 = 40.0;
  CHECK(gs::planning::validate(bad) == gs::planning::CatchParamError::bad_lead);
  bad.xy_lead_s = 0.0;  // the paper's manoeuvre: its thrust check says too low, not a bad lead
  CHECK(gs::planning::validate(bad) == gs::planning::CatchParamError::none);
}

TEST_CASE("the nominal inputs fly the trajectory through the vehicle model (4), (5)") {
  // Eq. (4) and (5) written out here (independently of the models): the thrust axis is the third
  // row of B_I R = R_x(phi) R_y(theta) R_z(psi), and the Euler rates are the inverse of the printed
  // matrix of (5) applied to Omega. Diagonal move with a yaw, so that every body rate is used.
  CatchTrajectoryParams p = fig7_params();
  p.start_xy_m = {-0.3, 0.4};
  p.target_xy_m = {0.5, -0.2};
  p.yaw_rad = 0.7;
  const auto traj = CatchTrajectory::create(p);
  REQUIRE(traj);

  using State = Eigen::Matrix<double, 9, 1>;  // p, v, phi, theta, psi
  auto passive = [](int axis, double a) {
    const double c = std::cos(a), s = std::sin(a);
    Eigen::Matrix3d r;
    if (axis == 0) r << 1, 0, 0, 0, c, s, 0, -s, c;
    if (axis == 1) r << c, 0, -s, 0, 1, 0, s, 0, c;
    if (axis == 2) r << c, s, 0, -s, c, 0, 0, 0, 1;
    return r;
  };
  auto f = [&](double t, const State& s) {
    const auto ref = traj->reference(t);
    const double phi = s(6), theta = s(7), psi = s(8);
    const Eigen::Matrix3d BI = passive(0, phi) * passive(1, theta) * passive(2, psi);
    Eigen::Matrix3d W;
    W << 1, 0, -std::sin(theta), 0, std::cos(phi), std::sin(phi) * std::cos(theta), 0, -std::sin(phi),
        std::cos(phi) * std::cos(theta);
    State d;
    d.segment<3>(0) = s.segment<3>(3);
    d.segment<3>(3) = BI.transpose() * Eigen::Vector3d(0, 0, ref.thrust_mps2) - Eigen::Vector3d(0, 0, kG);
    d.segment<3>(6) = W.inverse() * ref.body_rates_radps;
    return d;
  };
  State s = State::Zero();
  s.segment<3>(0) = traj->reference(0.0).position_m;
  s(8) = p.yaw_rad;
  double max_pos_err = 0.0, max_att_err = 0.0, max_rate = 0.0;
  // The body rates jump where the z jerk does (phase boundaries): RK4 steps end on them.
  const auto& phases = traj->z_manoeuvre().phase_times_s();
  for (int ph = 0; ph < 5; ++ph) {
    const int n = std::max(1, static_cast<int>(std::ceil((phases[ph + 1] - phases[ph]) / 1e-4)));
    const double h = (phases[ph + 1] - phases[ph]) / n;
    for (int k = 0; k < n; ++k) {
      const double t = phases[ph] + k * h;
      const State k1 = f(t, s);
      const State k2 = f(t + 0.5 * h, s + 0.5 * h * k1);
      const State k3 = f(t + 0.5 * h, s + 0.5 * h * k2);
      // The last stage just inside the phase, on the side whose inputs this phase uses.
      const State k4 = f((k + 1 == n) ? t + h - 1e-11 : t + h, s + h * k3);
      s += h / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4);
      const auto ref = traj->reference(t + h);
      max_pos_err = std::max(max_pos_err, (s.segment<3>(0) - ref.position_m).norm());
      max_att_err = std::max({max_att_err, std::abs(s(6) - ref.roll_rad), std::abs(s(7) - ref.pitch_rad),
                              std::abs(s(8) - p.yaw_rad)});
      max_rate = std::max(max_rate, ref.body_rates_radps.cwiseAbs().minCoeff());
    }
  }
  CHECK(max_rate > 0.1);  // all three body rates really were exercised
  CHECK(max_pos_err < 1e-8);
  CHECK(max_att_err < 1e-8);
  const auto end = traj->reference(traj->duration_s());
  CHECK((s.segment<3>(3) - end.velocity_mps).norm() < 1e-8);
}

TEST_CASE("nominal inputs: hover, and (47) as a derivative of the thrust direction") {
  const auto hover = gs::planning::nominal_inputs(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 0.3);
  CHECK(hover.thrust_mps2 == Approx(kG));
  CHECK(hover.body_rates_radps.norm() == 0.0);
  CHECK(hover.roll_rad == 0.0);
  CHECK(hover.pitch_rad == 0.0);
  // Tilt forward: x'' = g tan(theta) at level height.
  const auto fwd =
      gs::planning::nominal_inputs(Eigen::Vector3d(kG * std::tan(0.3), 0, 0), Eigen::Vector3d::Zero(), 0.0);
  CHECK(fwd.pitch_rad == Approx(0.3));
  CHECK(fwd.roll_rad == Approx(0.0).margin(1e-15));
  // Positive y acceleration needs negative roll (thrust axis (.., -sin phi, ..)).
  const auto left = gs::planning::nominal_inputs(Eigen::Vector3d(0, 2.0, 0), Eigen::Vector3d::Zero(), 0.0);
  CHECK(left.roll_rad < 0.0);
}

TEST_CASE("feasibility: small moves are feasible and certified") {
  const InputLimits limits;  // a_q in [1, 20], |Omega| <= 10
  auto p = fig7_params();
  const auto fig7 = CatchTrajectory::create(p);
  REQUIRE(fig7);
  const auto v = fig7->check_feasibility(limits);
  CHECK(v.feasible());
  CHECK(v.certified);
  CHECK(v.reason == Feasibility::feasible);
  p.target_xy_m = {0.03, -0.02};
  const auto tiny = CatchTrajectory::create(p);
  CHECK(tiny->check_feasibility(limits).feasible());
  p.target_xy_m = p.start_xy_m;  // no move at all
  CHECK(CatchTrajectory::create(p)->check_feasibility(limits).feasible());
}

TEST_CASE("feasibility: a huge move in a short T_xy is infeasible") {
  auto p = fig7_params();
  p.target_xy_m = {3.0, 2.0};
  p.t_xy_s = 0.4;
  const auto traj = CatchTrajectory::create(p);
  REQUIRE(traj);
  const auto v = traj->check_feasibility(InputLimits{});
  CHECK_FALSE(v.feasible());
  CHECK((v.reason == Feasibility::thrust_too_high || v.reason == Feasibility::rates_too_high));
  CHECK(v.thrust_high.violated);
  CHECK(v.rates.violated);
  // The reported worst values are the trajectory's own inputs at the reported instants.
  const auto r_thrust = traj->reference(v.thrust_high.t_s);
  CHECK(v.thrust_high.value == Approx(r_thrust.thrust_mps2).epsilon(1e-9));
  const auto r_rates = traj->reference(v.rates.t_s);
  CHECK(v.rates.value == Approx(r_rates.body_rates_radps.cwiseAbs().maxCoeff()).epsilon(1e-9));
  CHECK(v.rates.value == Approx(std::abs(r_rates.body_rates_radps(v.rates.axis))).epsilon(1e-9));
  // ... and they are the worst of a 0.1 ms brute-force scan, to the 1 ms scan resolution.
  const Scan scan = brute_force(*traj, 1e-4);
  CHECK(v.thrust_high.value == Approx(scan.thrust_max).epsilon(1e-3));
  CHECK(v.rates.value == Approx(scan.rate_max).epsilon(1e-3));
}

TEST_CASE("feasibility: rates alone too high") {
  auto p = fig7_params();
  p.target_xy_m = {0.12, 0.0};
  p.t_xy_s = 0.35;
  const auto traj = CatchTrajectory::create(p);
  REQUIRE(traj);
  const auto v = traj->check_feasibility(InputLimits{});
  CHECK(v.reason == Feasibility::rates_too_high);
  CHECK_FALSE(v.thrust_high.violated);
  CHECK_FALSE(v.thrust_low.violated);
  CHECK(v.rates.axis == 1);  // a move along x with zero yaw pitches: Omega_y
  CHECK(v.rates.value > 10.0);
  CHECK(v.rates.t_s >= traj->xy_start_time_s());
  const Scan scan = brute_force(*traj, 1e-4);
  CHECK(scan.rate_max > 10.0);
  CHECK(scan.thrust_max < 20.0);
}

TEST_CASE("feasibility: a_max too large makes the thrust too high") {
  auto p = fig7_params();
  p.a_max_mps2 = 7.0;  // g + a_max = 16.81 during the hold
  const auto traj = CatchTrajectory::create(p);
  REQUIRE(traj);
  const auto v = traj->check_feasibility(InputLimits{0.5, 15.0, 10.0});
  CHECK(v.reason == Feasibility::thrust_too_high);
  CHECK(v.thrust_high.value >= kG + 7.0 - 1e-9);
  CHECK(v.thrust_high.t_s >= traj->z_manoeuvre().phase_times_s()[3]);
  CHECK_FALSE(v.thrust_low.violated);
  // With the default limits an a_max above 20 - g breaks both thrust limits; the reason names
  // the upper one first and the lower one is reported too.
  p.a_max_mps2 = 10.5;
  const auto both = CatchTrajectory::create(p)->check_feasibility(InputLimits{});
  CHECK(both.reason == Feasibility::thrust_too_high);
  CHECK(both.thrust_low.violated);
  CHECK(both.thrust_low.value == Approx(kG - 10.5));
}

TEST_CASE("feasibility: a very deep drop needs too little thrust") {
  auto p = fig7_params();
  p.a_max_mps2 = 9.0;
  p.t_xy_s = 1.5;
  const auto traj = CatchTrajectory::create(p);
  REQUIRE(traj);
  CHECK(traj->start_height_m() - p.catch_height_m > 25.0);
  const auto v = traj->check_feasibility(InputLimits{});
  CHECK(v.reason == Feasibility::thrust_too_low);
  CHECK(v.thrust_low.value == Approx(kG - 9.0));
  const auto& t = traj->z_manoeuvre().phase_times_s();
  CHECK(v.thrust_low.t_s >= t[1] - 1e-12);
  CHECK(v.thrust_low.t_s <= t[2] + 1e-12);
  CHECK(traj->reference(v.thrust_low.t_s).thrust_mps2 == Approx(kG - 9.0));
}

TEST_CASE("feasibility agrees with a brute-force scan on random manoeuvres") {
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> pos(-1.0, 1.0), txy(0.3, 1.0), amax(0.0, 9.5), kmax(10.0, 40.0),
      yaw(-3.0, 3.0), rate(3.0, 15.0), thrust_hi(12.0, 22.0), lead(0.0, 0.6);
  int feasible = 0, infeasible = 0;
  for (int trial = 0; trial < 300; ++trial) {
    CatchTrajectoryParams p;
    p.start_xy_m = {pos(rng), pos(rng)};
    p.target_xy_m = {pos(rng), pos(rng)};
    p.catch_height_m = 1.0;
    p.k_max_mps3 = kmax(rng);
    p.t_xy_s = txy(rng);
    p.a_max_mps2 = std::min(amax(rng), p.k_max_mps3 * p.t_xy_s);
    p.yaw_rad = yaw(rng);
    // Half with the correction reaching into the dive, at most back to the start (t3).
    if (trial % 2 == 1) p.xy_lead_s = std::min(lead(rng), 2.0 * p.a_max_mps2 / p.k_max_mps3 + p.t_xy_s);
    const InputLimits limits{1.0, thrust_hi(rng), rate(rng)};
    const auto traj = CatchTrajectory::create(p);
    REQUIRE(traj);
    const auto v = traj->check_feasibility(limits);
    const Scan scan = brute_force(*traj, 2e-4);
    CAPTURE(trial, p.t_xy_s, p.xy_lead_s, p.a_max_mps2, p.k_max_mps3, limits.a_q_max_mps2,
            limits.omega_max_radps);
    if (v.feasible()) {
      ++feasible;
      // Certified: nothing anywhere violates the limits.
      if (v.certified) {
        CHECK(scan.thrust_max <= limits.a_q_max_mps2);
        CHECK(scan.thrust_min >= limits.a_q_min_mps2);
        CHECK(scan.rate_max <= limits.omega_max_radps);
      }
    } else {
      ++infeasible;
      const auto& w = v.primary();
      CHECK(w.violated);
      // The violation is real: the trajectory's own inputs at that instant break the limit.
      const auto r = traj->reference(w.t_s);
      if (v.reason == Feasibility::rates_too_high) {
        CHECK(r.body_rates_radps.cwiseAbs().maxCoeff() > limits.omega_max_radps);
      } else if (v.reason == Feasibility::thrust_too_high) {
        CHECK(r.thrust_mps2 > limits.a_q_max_mps2);
      } else {
        CHECK(r.acceleration_mps2.z() + kG < limits.a_q_min_mps2);
      }
      // Each reported violation is the worst, to the 1 ms scan resolution. At rest the check's
      // extreme is exact and the brute-force grid may step past it, by up to k_max x its step
      // (an instant's extreme when the hold is near zero).
      const double grid_margin = p.k_max_mps3 * 2e-4;
      if (v.rates.violated) CHECK(v.rates.value == Approx(scan.rate_max).epsilon(2e-3));
      if (v.thrust_high.violated)
        CHECK(v.thrust_high.value == Approx(scan.thrust_max).epsilon(2e-3).margin(grid_margin));
      if (v.thrust_low.violated)
        CHECK(v.thrust_low.value == Approx(scan.thrust_min).epsilon(2e-3).margin(grid_margin));
    }
    // Anything the scan sees violated is reported infeasible (beyond the scan's own resolution).
    if (scan.rate_max > limits.omega_max_radps * 1.001 || scan.thrust_max > limits.a_q_max_mps2 * 1.001 ||
        scan.thrust_min < limits.a_q_min_mps2 * 0.999) {
      CHECK_FALSE(v.feasible());
    }
  }
  CHECK(feasible > 20);
  CHECK(infeasible > 20);
}
