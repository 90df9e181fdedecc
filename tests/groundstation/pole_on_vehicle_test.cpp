// The pole on the vehicle, eq. (23)-(31): the equations of motion (28), (29) against the
// Euler-Lagrange equations evaluated numerically from the Lagrangian (25)-(27), energy
// conservation on a pivot at rest, and the planar pendulum of docs/paper-notes.md.
#include "groundstation/model/pole_on_vehicle.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "groundstation/model/planar_pole_vehicle.hpp"
#include "groundstation/model/rk4.hpp"

namespace {

using gs::model::PoleOnVehicleState;
using gs::model::PoleParams;

constexpr double kL = pa::kPoleHalfLength_m;
constexpr double kG = pa::kGravity_mps2;

// The pivot moves with constant acceleration A: p(t) = p0 + v0 t + A t^2 / 2.
struct Pivot {
  Eigen::Vector3d p0, v0, acc;
  Eigen::Vector3d p(double t) const { return p0 + v0 * t + 0.5 * acc * t * t; }
  Eigen::Vector3d v(double t) const { return v0 + acc * t; }
};

// Lag(q, q', t) for q = (a, b) through the model's Lagrangian (25)-(27).
double lagrangian(const Eigen::Vector2d& q, const Eigen::Vector2d& q_dot, double t, const Pivot& pivot,
                  const PoleParams& params) {
  return gs::model::pole_on_vehicle_lagrangian_J({q.x(), q.y(), q_dot.x(), q_dot.y()}, pivot.p(t), pivot.v(t),
                                                 params);
}

// q'' from d/dt dLag/dq' - dLag/dq = 0 with every derivative by central differences:
//   M q'' = dLag/dq - (d2Lag/dq' dq) q' - d2Lag/dq' dt,   M = d2Lag/dq'^2.
Eigen::Vector2d euler_lagrange_acceleration(const Eigen::Vector2d& q, const Eigen::Vector2d& q_dot,
                                            const Pivot& pivot, const PoleParams& params) {
  const double h = 5e-5;  // truncation ~h^2 above, round-off ~eps/h^2 below: ~2e-6 here
  const auto lag = [&](const Eigen::Vector2d& qq, const Eigen::Vector2d& qd, double t) {
    return lagrangian(qq, qd, t, pivot, params);
  };
  const auto e = [](int i) { return Eigen::Vector2d::Unit(i); };
  // dLag/dq' as a function, differentiated once more below.
  const auto momentum = [&](const Eigen::Vector2d& qq, const Eigen::Vector2d& qd, double t, int i) {
    return (lag(qq, qd + h * e(i), t) - lag(qq, qd - h * e(i), t)) / (2 * h);
  };
  Eigen::Matrix2d mass;
  Eigen::Matrix2d mixed;  // d2Lag / dq'_i dq_j
  Eigen::Vector2d time_derivative;
  Eigen::Vector2d force;
  for (int i = 0; i < 2; ++i) {
    for (int j = 0; j < 2; ++j) {
      mass(i, j) = (momentum(q, q_dot + h * e(j), 0.0, i) - momentum(q, q_dot - h * e(j), 0.0, i)) / (2 * h);
      mixed(i, j) = (momentum(q + h * e(j), q_dot, 0.0, i) - momentum(q - h * e(j), q_dot, 0.0, i)) / (2 * h);
    }
    time_derivative(i) = (momentum(q, q_dot, h, i) - momentum(q, q_dot, -h, i)) / (2 * h);
    force(i) = (lag(q + h * e(i), q_dot, 0.0) - lag(q - h * e(i), q_dot, 0.0)) / (2 * h);
  }
  return mass.fullPivLu().solve(force - mixed * q_dot - time_derivative);
}

double tilt_from_vertical(const PoleOnVehicleState& s) { return std::asin(std::hypot(s.a_m, s.b_m) / kL); }

}  // namespace

TEST_CASE("eq. (28), (29) agree with Euler-Lagrange on the Lagrangian (25)-(27)", "[pole_on_vehicle]") {
  const PoleParams params;
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double worst = 0.0;
  for (int i = 0; i < 100; ++i) {
    const double tilt = 1.2 * std::abs(u(rng));
    const double azimuth = M_PI * u(rng);
    PoleOnVehicleState s{kL * std::sin(tilt) * std::cos(azimuth), kL * std::sin(tilt) * std::sin(azimuth),
                         2.0 * u(rng), 2.0 * u(rng)};
    const Pivot pivot{Eigen::Vector3d(u(rng), u(rng), 1.0 + u(rng)),
                      Eigen::Vector3d(2 * u(rng), 2 * u(rng), 2 * u(rng)),
                      Eigen::Vector3d(8 * u(rng), 8 * u(rng), 8 * u(rng))};
    const Eigen::Vector2d model = gs::model::pole_on_vehicle_acceleration_mps2(s, pivot.acc, params);
    const Eigen::Vector2d reference =
        euler_lagrange_acceleration({s.a_m, s.b_m}, {s.a_dot_mps, s.b_dot_mps}, pivot, params);
    const double error = (model - reference).norm() / std::max(1.0, reference.norm());
    worst = std::max(worst, error);
    INFO("sample " << i << " model " << model.transpose() << " EL " << reference.transpose());
    CHECK(error < 1e-5);
  }
  std::printf("pole on vehicle: worst relative deviation from numerical Euler-Lagrange %.1e\n", worst);
}

TEST_CASE("planar case b = 0: (4/3) L alpha'' = a_q sin(alpha - theta)", "[pole_on_vehicle]") {
  const PoleParams params;
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 100; ++i) {
    const double alpha = 1.3 * u(rng);
    const double alpha_dot = 4.0 * u(rng);
    const double theta = 0.8 * u(rng);
    const double a_q = 10.0 + 9.0 * u(rng);
    // Pivot acceleration from eq. (4) in the plane.
    const Eigen::Vector3d pivot_acc =
        a_q * Eigen::Vector3d(std::sin(theta), 0.0, std::cos(theta)) - Eigen::Vector3d(0, 0, kG);
    const PoleOnVehicleState s{kL * std::sin(alpha), 0.0, kL * std::cos(alpha) * alpha_dot, 0.0};
    const Eigen::Vector2d acc = gs::model::pole_on_vehicle_acceleration_mps2(s, pivot_acc, params);
    // a = L sin alpha  =>  a'' = L cos(alpha) alpha'' - L sin(alpha) alpha'^2.
    const double alpha_ddot =
        (acc.x() + kL * std::sin(alpha) * alpha_dot * alpha_dot) / (kL * std::cos(alpha));
    CHECK(acc.y() == Approx(0.0).margin(1e-12));
    CHECK(alpha_ddot == Approx(a_q * std::sin(alpha - theta) / (4.0 / 3.0 * kL)).epsilon(1e-10));
    // The throw planner's planar model (planar_pole_vehicle.hpp) agrees.
    CHECK(alpha_ddot ==
          Approx(gs::model::planar_pole_angular_acceleration_radps2(theta, alpha, a_q)).epsilon(1e-10));
  }
}

TEST_CASE("pivot at rest: a falling pole conserves its energy", "[pole_on_vehicle]") {
  // Normal gravity: the upright is unstable and the pole falls; run until it is 80 deg down.
  const PoleParams params;
  PoleOnVehicleState s{0.02, -0.01, 0.3, 0.25};
  const Eigen::Vector3d p0(0.5, -0.5, 1.0);
  const Eigen::Vector3d v0 = Eigen::Vector3d::Zero();
  const Eigen::Vector3d still = Eigen::Vector3d::Zero();
  const double e0 = gs::model::pole_on_vehicle_energy_J(s, p0, v0, params);
  const auto f = [&](const PoleOnVehicleState& x) {
    return gs::model::pole_on_vehicle_derivative(x, still, params);
  };
  double worst = 0.0;
  int steps = 0;
  while (tilt_from_vertical(s) < 80.0 * M_PI / 180.0 && steps < 100000) {
    s = gs::model::rk4_step(f, s, 1e-3);
    ++steps;
    worst = std::max(worst, std::abs(gs::model::pole_on_vehicle_energy_J(s, p0, v0, params) - e0));
  }
  CHECK(steps < 100000);
  CHECK(worst < 1e-7);  // RK4 error; a wrong equation of motion errs by ~1e-2 J
}

TEST_CASE("pivot at rest, gravity reversed: a long spherical swing conserves energy", "[pole_on_vehicle]") {
  // With g -> -g the upright is the stable equilibrium, so the pole swings for a long time
  // inside the domain of (24) (the upper half-sphere), in a genuinely 3D (precessing) orbit.
  PoleParams params;
  params.gravity_mps2 = -kG;
  PoleOnVehicleState s{0.25, 0.0, 0.0, 0.9};
  const Eigen::Vector3d p0 = Eigen::Vector3d::Zero();
  const Eigen::Vector3d still = Eigen::Vector3d::Zero();
  const double e0 = gs::model::pole_on_vehicle_energy_J(s, p0, still, params);
  const auto f = [&](const PoleOnVehicleState& x) {
    return gs::model::pole_on_vehicle_derivative(x, still, params);
  };
  double worst = 0.0;
  double max_tilt = 0.0;
  double lz0 = s.a_m * s.b_dot_mps - s.b_m * s.a_dot_mps;  // angular momentum about z (conserved)
  double worst_lz = 0.0;
  for (int i = 0; i < 30000; ++i) {  // 30 s
    s = gs::model::rk4_step(f, s, 1e-3);
    worst = std::max(worst, std::abs(gs::model::pole_on_vehicle_energy_J(s, p0, still, params) - e0));
    worst_lz = std::max(worst_lz, std::abs(s.a_m * s.b_dot_mps - s.b_m * s.a_dot_mps - lz0));
    max_tilt = std::max(max_tilt, tilt_from_vertical(s));
  }
  CHECK(max_tilt < 1.2);
  CHECK(worst < 1e-9);
  CHECK(worst_lz < 1e-9);
}

TEST_CASE("eq. (30): f_qp drives the pole with the vehicle's acceleration", "[pole_on_vehicle]") {
  const PoleParams params;
  gs::model::VehiclePoleState s;
  s.vehicle.theta_rad = -0.48;
  s.vehicle.v_mps = Eigen::Vector3d(0.3, 0.0, 5.5);
  s.pole = {kL * std::sin(0.48), 0.05, kL * std::cos(0.48) * 2.5, 0.1};
  gs::model::VehicleInput input;
  input.a_q_mps2 = 4.48;
  input.omega_radps = Eigen::Vector3d(0.0, 2.5, 0.0);
  const gs::model::VehiclePoleState rate = gs::model::vehicle_pole_dynamics(s, input, params);
  const gs::model::VehicleState vehicle_rate = gs::model::vehicle_dynamics(s.vehicle, input);
  CHECK((rate.vehicle.v_mps - vehicle_rate.v_mps).norm() < 1e-15);
  CHECK(rate.vehicle.theta_rad == vehicle_rate.theta_rad);
  const Eigen::Vector2d acc =
      gs::model::pole_on_vehicle_acceleration_mps2(s.pole, vehicle_rate.v_mps, params);
  CHECK(rate.pole.a_m == s.pole.a_dot_mps);
  CHECK(rate.pole.b_m == s.pole.b_dot_mps);
  CHECK(rate.pole.a_dot_mps == acc.x());
  CHECK(rate.pole.b_dot_mps == acc.y());
}

TEST_CASE("eq. (23)-(27): on-vehicle and free-flight states convert both ways", "[pole_on_vehicle]") {
  const PoleParams params;
  const PoleOnVehicleState s{0.2, -0.15, 0.7, -1.1};
  const Eigen::Vector3d p(1.0, 2.0, 3.0);
  const Eigen::Vector3d v(0.3, -0.2, 4.0);
  const gs::model::PoleState free = gs::model::free_flight_state_from_pole_on_vehicle(s, p, v, params);
  CHECK(free.n.norm() == Approx(1.0));
  CHECK((free.p_m - (p + kL * free.n)).norm() < 1e-15);
  CHECK(std::abs(free.omega_radps.dot(free.n)) < 1e-15);
  // The same rigid-body motion: the centre's velocity is the pivot's plus Omega x L n.
  CHECK((free.v_mps - (v + free.omega_radps.cross(kL * free.n))).norm() < 1e-14);
  CHECK(gs::model::pole_energy_J(free, params) ==
        Approx(gs::model::pole_on_vehicle_energy_J(s, p, v, params)).epsilon(1e-14));
  const PoleOnVehicleState back = gs::model::pole_on_vehicle_state_from_free_flight(free, params);
  CHECK(back.a_m == Approx(s.a_m));
  CHECK(back.b_m == Approx(s.b_m));
  CHECK(back.a_dot_mps == Approx(s.a_dot_mps));
  CHECK(back.b_dot_mps == Approx(s.b_dot_mps));
}
