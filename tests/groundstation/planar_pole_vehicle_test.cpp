// The planar quadrocopter-pole model (Section III-A): pendulum equation, normal force and the
// launch condition, checked against physics that does not share the model's derivation.
#include "groundstation/model/planar_pole_vehicle.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <functional>
#include <unsupported/Eigen/AutoDiff>

namespace {

using gs::model::PlanarInput;
using gs::model::PlanarPoleVehicleParams;
using gs::model::PlanarState;
namespace planar = gs::model::planar;

constexpr double kL = pa::kPoleHalfLength_m;
constexpr double kG = pa::kGravity_mps2;

template <int N>
using Vec = Eigen::Matrix<double, N, 1>;

template <int N>
Vec<N> rk4_step(const std::function<Vec<N>(double, const Vec<N>&)>& f, double t, const Vec<N>& y, double h) {
  const Vec<N> k1 = f(t, y);
  const Vec<N> k2 = f(t + 0.5 * h, y + 0.5 * h * k1);
  const Vec<N> k3 = f(t + 0.5 * h, y + 0.5 * h * k2);
  const Vec<N> k4 = f(t + h, y + h * k3);
  return y + (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
}

// Energy per unit pole mass of the rod about a pivot that feels the constant effective gravity
// a_q along -(sin theta, cos theta): kinetic (1/2)(4/3) L^2 alpha'^2 plus potential of the centre.
double pivot_frame_energy_per_mass(double theta, double alpha, double alpha_dot, double a_q) {
  return (2.0 / 3.0) * kL * kL * alpha_dot * alpha_dot + a_q * kL * std::cos(alpha - theta);
}

// The prescribed pivot motion for the independent simulation: a varying thrust and pitch.
double thrust_profile(double t) { return kG + 1.5 + 3.0 * std::sin(2.0 * t); }
double pitch_rate_profile(double t) { return 0.9 * std::cos(1.5 * t); }

// Independent simulation: the rod as a free rigid body in maximal coordinates (centre x_c, z_c,
// angle phi from the vertical towards +x, i.e. a rotation about +y), held to the pivot by a
// bilateral constraint whose force is solved for at every evaluation (Newton-Euler plus the
// acceleration-level constraint, with Baumgarte stabilisation). State layout:
//   0..4 pivot (x, z, vx, vz, theta), 5..10 rod (x_c, z_c, vx_c, vz_c, phi, phi_dot).
struct ConstrainedRod {
  double mass_kg = pa::kPoleMass_kg;
  double baumgarte_radps = 20.0;

  struct Solution {
    Vec<11> derivative;
    Eigen::Vector2d constraint_force_N;  // on the rod, from the vehicle
  };

  Solution evaluate(double t, const Vec<11>& y) const {
    const double a_q = thrust_profile(t);
    const double theta = y(4);
    const Eigen::Vector2d pivot_acc(a_q * std::sin(theta), a_q * std::cos(theta) - kG);
    const double phi = y(9), phi_dot = y(10);
    const double inertia = mass_kg * kL * kL / 3.0;  // thin rod about its centre, eq. (9)
    // Position and velocity error of the constraint p_c - L e(phi) - p_q = 0.
    const Eigen::Vector2d c(y(5) - kL * std::sin(phi) - y(0), y(6) - kL * std::cos(phi) - y(1));
    const Eigen::Vector2d c_dot(y(7) - kL * std::cos(phi) * phi_dot - y(2),
                                y(8) + kL * std::sin(phi) * phi_dot - y(3));
    // Unknowns (xc'', zc'', phi'', lambda_x, lambda_z).
    Eigen::Matrix<double, 5, 5> a = Eigen::Matrix<double, 5, 5>::Zero();
    Vec<5> b = Vec<5>::Zero();
    // Newton: m p_c'' = lambda + m (0, -g).
    a(0, 0) = mass_kg;
    a(0, 3) = -1.0;
    a(1, 1) = mass_kg;
    a(1, 4) = -1.0;
    b(1) = -mass_kg * kG;
    // Euler about +y: Theta phi'' = (r x lambda)_y = r_z lambda_x - r_x lambda_z, with r the lever
    // from the centre to the pivot, r = -L (sin phi, cos phi).
    const double r_x = -kL * std::sin(phi), r_z = -kL * std::cos(phi);
    a(2, 2) = inertia;
    a(2, 3) = -r_z;
    a(2, 4) = r_x;
    // Constraint acceleration: p_c'' - L (cos phi phi'' - sin phi phi'^2,
    //                                     -sin phi phi'' - cos phi phi'^2) = p_q'' - stabilisation.
    const double beta = baumgarte_radps;
    const Eigen::Vector2d stab = 2.0 * beta * c_dot + beta * beta * c;
    a(3, 0) = 1.0;
    a(3, 2) = -kL * std::cos(phi);
    b(3) = pivot_acc.x() - kL * std::sin(phi) * phi_dot * phi_dot - stab.x();
    a(4, 1) = 1.0;
    a(4, 2) = kL * std::sin(phi);
    b(4) = pivot_acc.y() - kL * std::cos(phi) * phi_dot * phi_dot - stab.y();
    const Vec<5> sol = a.partialPivLu().solve(b);

    Solution out;
    out.derivative << y(2), y(3), pivot_acc.x(), pivot_acc.y(), pitch_rate_profile(t), y(7), y(8), sol(0),
        sol(1), phi_dot, sol(2);
    out.constraint_force_N = sol.segment<2>(3);
    return out;
  }
};

}  // namespace

TEST_CASE("the upright pole is an unstable equilibrium of the hovering vehicle", "[planar_pole_vehicle]") {
  PlanarState<double> s = PlanarState<double>::Zero();
  PlanarInput<double> u(kG, 0.0);
  CHECK(gs::model::planar_pole_vehicle_dynamics<double>(s, u).norm() == Approx(0.0).margin(1e-12));
  s(planar::kAlpha) = 0.01;
  // A small tilt towards +x accelerates further towards +x: (4/3) L alpha'' = g sin alpha.
  const double alpha_ddot = gs::model::planar_pole_vehicle_dynamics<double>(s, u)(planar::kAlphaDot);
  CHECK(alpha_ddot == Approx(0.75 * kG * std::sin(0.01) / kL).epsilon(1e-12));
  CHECK(alpha_ddot > 0.0);
}

TEST_CASE("the vehicle's translation follows the thrust direction (sin theta, cos theta)",
          "[planar_pole_vehicle]") {
  PlanarState<double> s = PlanarState<double>::Zero();
  s(planar::kVx) = 0.3;
  s(planar::kVz) = -0.2;
  s(planar::kTheta) = 0.4;
  s(planar::kAlphaDot) = 1.1;
  const PlanarInput<double> u(12.0, -2.0);
  const PlanarState<double> d = gs::model::planar_pole_vehicle_dynamics<double>(s, u);
  CHECK(d(planar::kX) == 0.3);
  CHECK(d(planar::kZ) == -0.2);
  CHECK(d(planar::kVx) == Approx(12.0 * std::sin(0.4)));
  CHECK(d(planar::kVz) == Approx(12.0 * std::cos(0.4) - kG));
  CHECK(d(planar::kTheta) == -2.0);
  CHECK(d(planar::kAlpha) == 1.1);
}

TEST_CASE("with the pivot hovering (a_q = g, theta = 0) the rod conserves its energy",
          "[planar_pole_vehicle]") {
  // A full swing through large angles, not just small oscillations.
  Vec<7> s = Vec<7>::Zero();
  s(planar::kAlpha) = 0.3;
  s(planar::kAlphaDot) = -0.5;
  const PlanarInput<double> u(kG, 0.0);
  const auto f = [&](double, const Vec<7>& y) -> Vec<7> {
    return gs::model::planar_pole_vehicle_dynamics<double>(y, u);
  };
  const double e0 = pivot_frame_energy_per_mass(0.0, s(planar::kAlpha), s(planar::kAlphaDot), kG);
  double max_alpha = 0.0;
  double max_drift = 0.0;
  const double h = 1e-4;
  for (int k = 0; k < 30000; ++k) {
    s = rk4_step<7>(f, k * h, s, h);
    max_alpha = std::max(max_alpha, std::abs(s(planar::kAlpha)));
    const double e = pivot_frame_energy_per_mass(0.0, s(planar::kAlpha), s(planar::kAlphaDot), kG);
    max_drift = std::max(max_drift, std::abs(e - e0));
  }
  CHECK(max_alpha > 3.0);  // the pole fell over and swung through the bottom
  CHECK(max_drift < 1e-9 * std::abs(e0) + 1e-12);
  // The vehicle's translation and pitch are untouched by the pole (Section II).
  CHECK(s.head<5>().norm() == Approx(0.0).margin(1e-12));
}

TEST_CASE("at a tilted constant thrust the rod swings about the thrust axis, conserving energy",
          "[planar_pole_vehicle]") {
  Vec<7> s = Vec<7>::Zero();
  s(planar::kTheta) = -0.35;
  s(planar::kAlpha) = -0.2;
  s(planar::kAlphaDot) = 0.4;
  const PlanarInput<double> u(6.0, 0.0);
  const auto f = [&](double, const Vec<7>& y) -> Vec<7> {
    return gs::model::planar_pole_vehicle_dynamics<double>(y, u);
  };
  const double e0 = pivot_frame_energy_per_mass(-0.35, -0.2, 0.4, 6.0);
  const double h = 1e-4;
  for (int k = 0; k < 20000; ++k) s = rk4_step<7>(f, k * h, s, h);
  CHECK(pivot_frame_energy_per_mass(-0.35, s(planar::kAlpha), s(planar::kAlphaDot), 6.0) ==
        Approx(e0).epsilon(1e-9));
}

TEST_CASE("F_N equals the plate-normal contact force of an independent Newton-Euler simulation",
          "[planar_pole_vehicle]") {
  // Pivot starts hovering with the pole tilted and spinning; the prescribed thrust and pitch
  // profiles then shake it. The maximal-coordinate simulation never uses the pendulum equation.
  ConstrainedRod rod;
  Vec<11> y = Vec<11>::Zero();
  const double alpha0 = 0.25, alpha_dot0 = -4.5;
  y(9) = alpha0;
  y(10) = alpha_dot0;
  y(5) = kL * std::sin(alpha0);
  y(6) = kL * std::cos(alpha0);
  y(7) = kL * std::cos(alpha0) * alpha_dot0;
  y(8) = -kL * std::sin(alpha0) * alpha_dot0;

  // The reduced model, integrated alongside from the same initial condition.
  Vec<7> s = Vec<7>::Zero();
  s(planar::kAlpha) = alpha0;
  s(planar::kAlphaDot) = alpha_dot0;
  const auto reduced = [](double t, const Vec<7>& x) -> Vec<7> {
    const PlanarInput<double> u(thrust_profile(t), pitch_rate_profile(t));
    return gs::model::planar_pole_vehicle_dynamics<double>(x, u);
  };
  const auto maximal = [&](double t, const Vec<11>& x) -> Vec<11> { return rod.evaluate(t, x).derivative; };

  const double h = 2e-4;
  double max_force_error = 0.0, max_alpha_error = 0.0, min_fn = 1e9, max_fn = -1e9;
  for (int k = 0; k <= 7500; ++k) {  // 1.5 s
    const double t = k * h;
    if (k % 50 == 0) {
      const ConstrainedRod::Solution sol = rod.evaluate(t, y);
      const double theta = y(4);
      const double fn_newton =
          sol.constraint_force_N.dot(Eigen::Vector2d(std::sin(theta), std::cos(theta))) / rod.mass_kg;
      const double fn_model =
          gs::model::planar_normal_force_per_mass_mps2<double>(theta, y(9), y(10), thrust_profile(t));
      max_force_error = std::max(max_force_error, std::abs(fn_newton - fn_model));
      max_alpha_error = std::max(max_alpha_error, std::abs(y(9) - s(planar::kAlpha)));
      min_fn = std::min(min_fn, fn_model);
      max_fn = std::max(max_fn, fn_model);
    }
    y = rk4_step<11>(maximal, t, y, h);
    s = rk4_step<7>(reduced, t, s, h);
  }
  // The run covers both a pressing and a pulling contact, so the sign of every term is tested.
  CHECK(min_fn < 0.0);
  CHECK(max_fn > 5.0);
  CHECK(max_force_error < 1e-8);
  CHECK(max_alpha_error < 1e-8);
}

TEST_CASE("the AutoDiff instantiation matches finite differences of the double one",
          "[planar_pole_vehicle]") {
  using Ad = Eigen::AutoDiffScalar<Eigen::Matrix<double, 9, 1>>;
  Vec<9> z;
  z << 0.2, 1.1, -0.4, 2.0, -0.3, 0.45, 1.7, 7.5, 1.2;
  PlanarState<Ad> s;
  PlanarInput<Ad> u;
  for (int i = 0; i < 9; ++i) {
    Ad v(z(i), 9, i);
    if (i < 7) s(i) = v;
    else u(i - 7) = v;
  }
  const PlanarState<Ad> f = gs::model::planar_pole_vehicle_dynamics<Ad>(s, u);
  const Ad fn = gs::model::planar_normal_force_per_mass_mps2<Ad>(s, u);
  const auto eval = [](const Vec<9>& x) {
    Vec<8> out;
    const PlanarState<double> ss = x.head<7>();
    const PlanarInput<double> uu = x.tail<2>();
    out.head<7>() = gs::model::planar_pole_vehicle_dynamics<double>(ss, uu);
    out(7) = gs::model::planar_normal_force_per_mass_mps2<double>(ss, uu);
    return out;
  };
  const double eps = 1e-6;
  for (int j = 0; j < 9; ++j) {
    const Vec<9> dz = Vec<9>::Unit(j) * eps;
    const Vec<8> fd = (eval(z + dz) - eval(z - dz)) / (2.0 * eps);
    for (int i = 0; i < 7; ++i) CHECK(f(i).derivatives()(j) == Approx(fd(i)).margin(1e-8));
    CHECK(fn.derivatives()(j) == Approx(fd(7)).margin(1e-8));
  }
}

// The Fig. 5 end state as printed: alpha = 0.48, theta = -0.48, alpha' = 2.5, a_q = 4.48.
TEST_CASE("at the printed Fig. 5 launch state F_N is zero within one unit of the printed alpha'",
          "[planar_pole_vehicle]") {
  const double fn = gs::model::planar_normal_force_per_mass_mps2<double>(-0.48, 0.48, 2.5, 4.48);
  CHECK(fn == Approx(-0.1585).margin(5e-4));  // docs/paper-notes.md: about -0.16 m/s^2

  // "Zero within the rounding of the printed numbers" (docs/paper-notes.md): F_N is the small remainder of
  // terms of about 4.5 m/s^2 that cancel, and it is smaller than what one unit in the last printed
  // digit of alpha' (0.1 rad/s) changes: alpha' = 2.4154 (printed "2.4" at that precision, 0.085
  // below 2.5) makes it exactly zero (next test case).
  const double unit_of_alpha_dot =
      fn - gs::model::planar_normal_force_per_mass_mps2<double>(-0.48, 0.48, 2.4, 4.48);
  CHECK(std::abs(fn) < std::abs(unit_of_alpha_dot));
  CHECK(std::abs(fn) < 0.04 * 4.48);

  // Rounding band: every value that prints as the figure's digits (two decimals for the angles
  // and a_q, one for alpha' = 2.5). F_N is smooth and the box small, so a dense grid including the
  // corners gives its range.
  double lo = 1e9, hi = -1e9;
  const int n = 11;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k)
        for (int l = 0; l < n; ++l) {
          const double theta = -0.485 + 0.01 * i / (n - 1);
          const double alpha = 0.475 + 0.01 * j / (n - 1);
          const double alpha_dot = 2.45 + 0.1 * k / (n - 1);
          const double a_q = 4.475 + 0.01 * l / (n - 1);
          const double v = gs::model::planar_normal_force_per_mass_mps2<double>(theta, alpha, alpha_dot, a_q);
          lo = std::min(lo, v);
          hi = std::max(hi, v);
        }
  // The band does NOT reach zero: even the most favourable rounding leaves F_N at about
  // -0.06 m/s^2, so the printed a_q = 4.48 is not the launch thrust of the derived model
  // (see the launch-condition test). Pinned so that a change to the model shows here.
  CHECK(lo == Approx(-0.261).margin(2e-3));
  CHECK(hi == Approx(-0.0603).margin(2e-3));
  CHECK(hi < 0.0);

  // The printed eq. (33), taken literally, does vanish at the printed numbers (0.0035 m/s^2):
  // the figure's a_q = 4.48 appears to come from that expression.
  const double printed_33 = 4.48 * std::cos(-0.48) + 0.75 * std::sin(0.48) * std::sin(-0.48 - 0.48) -
                            kL * std::cos(-0.48) * 2.5 * 2.5;
  CHECK(printed_33 == Approx(0.0).margin(5e-3));
}

TEST_CASE("the launch condition F_N = 0 solved for a_q,T or for alpha'_T", "[planar_pole_vehicle]") {
  const double a_qT = gs::model::planar_launch_thrust_mps2(-0.48, 0.48, 2.5);
  CHECK(gs::model::planar_normal_force_per_mass_mps2<double>(-0.48, 0.48, 2.5, a_qT) ==
        Approx(0.0).margin(1e-12));
  CHECK(a_qT == Approx(4.7991).margin(1e-4));  // 0.319 m/s^2 (7 %) above the printed 4.48
  CHECK(a_qT - 4.48 == Approx(0.3191).margin(1e-4));

  const double alpha_dot_T = gs::model::planar_launch_pole_rate_radps(-0.48, 0.48, 4.48);
  CHECK(gs::model::planar_normal_force_per_mass_mps2<double>(-0.48, 0.48, alpha_dot_T, 4.48) ==
        Approx(0.0).margin(1e-12));
  CHECK(alpha_dot_T == Approx(2.4154).margin(1e-4));  // 0.085 rad/s below the printed 2.5

  // F_N grows with thrust and falls with pole rate: more thrust keeps the pole on the plate.
  CHECK(gs::model::planar_normal_force_per_mass_mps2<double>(-0.48, 0.48, 2.5, a_qT + 0.01) > 0.0);
  CHECK(gs::model::planar_normal_force_per_mass_mps2<double>(-0.48, 0.48, 2.5 + 0.01, a_qT) < 0.0);
  // No real launch rate when the pole points below the plate's tangent.
  CHECK(std::isnan(gs::model::planar_launch_pole_rate_radps(0.0, 2.0, 5.0)));
}

TEST_CASE("the linearisation A = df/ds, B = df/du matches central differences", "[planar_pole_vehicle]") {
  PlanarState<double> s;
  s << 0.4, 1.2, 0.3, -0.8, -0.35, 0.6, 1.9;
  const PlanarInput<double> u(8.3, -1.4);
  const gs::model::PlanarLinearisation lin = gs::model::linearise_planar_pole_vehicle(s, u);
  const double eps = 1e-6;
  for (int i = 0; i < planar::kStateSize; ++i) {
    const PlanarState<double> ds = PlanarState<double>::Unit(i) * eps;
    const PlanarState<double> fd = (gs::model::planar_pole_vehicle_dynamics<double>(s + ds, u) -
                                    gs::model::planar_pole_vehicle_dynamics<double>(s - ds, u)) /
                                   (2.0 * eps);
    CHECK((lin.A.col(i) - fd).cwiseAbs().maxCoeff() < 1e-8);
  }
  for (int j = 0; j < planar::kInputSize; ++j) {
    const PlanarInput<double> du = PlanarInput<double>::Unit(j) * eps;
    const PlanarState<double> fd = (gs::model::planar_pole_vehicle_dynamics<double>(s, u + du) -
                                    gs::model::planar_pole_vehicle_dynamics<double>(s, u - du)) /
                                   (2.0 * eps);
    CHECK((lin.B.col(j) - fd).cwiseAbs().maxCoeff() < 1e-8);
  }
  // The structure the LQR designs rely on: the pitch rate drives theta only.
  CHECK(lin.B(planar::kTheta, planar::kPitchRate) == 1.0);
  CHECK(lin.B.col(planar::kPitchRate).cwiseAbs().sum() == 1.0);
}
