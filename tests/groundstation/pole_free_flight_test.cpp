// The pole in free flight, eq. (10)-(22): the drag integrals against a fine trapezoid of the
// printed integrands, the ballistic limit, energy dissipation, and the integrator.
#include "groundstation/model/pole_free_flight.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <random>

namespace {

using gs::model::PoleDrag;
using gs::model::PoleParams;
using gs::model::PoleState;

constexpr double kL = pa::kPoleHalfLength_m;
constexpr double kG = pa::kGravity_mps2;

// Eq. (10)-(15) literally, by the trapezoid rule with `intervals` panels.
PoleDrag trapezoid_drag(const PoleState& s, const PoleParams& p, int intervals) {
  PoleDrag d;
  const double length = p.half_length_m;
  for (int i = 0; i <= intervals; ++i) {
    const double xi = -length + 2.0 * length * i / intervals;
    const double weight = ((i == 0 || i == intervals) ? 0.5 : 1.0) * 2.0 * length / intervals;
    const Eigen::Vector3d v = s.v_mps + s.omega_radps.cross(xi * s.n);            // (12)
    const Eigen::Vector3d v_z = v.dot(s.n) * s.n;                                 // (13)
    const Eigen::Vector3d v_xy = v - v_z;                                         // (14)
    d.axial_force_N += -p.drag_axial * weight * v_z.norm() * v_z;                 // (10)
    d.normal_force_N += -p.drag_normal * weight * v_xy.norm() * v_xy;             // (11)
    d.torque_Nm += -p.drag_rotational * weight * (xi * s.n).cross(v.norm() * v);  // (15)
  }
  return d;
}

double relative_error(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return (a - b).norm() / std::max(b.norm(), 1e-300);
}

Eigen::Vector3d random_unit(std::mt19937& rng) {
  std::normal_distribution<double> n01;
  return Eigen::Vector3d(n01(rng), n01(rng), n01(rng)).normalized();
}

// Random pole states of the kinds the quadrature must handle: generic 3D, planar (the point of
// zero normal speed lies on the pole), nearly planar, broadside (no axial speed), no rotation.
PoleState random_pole_state(std::mt19937& rng, int kind) {
  std::normal_distribution<double> n01;
  PoleState s;
  s.n = random_unit(rng);
  s.omega_radps = 3.0 * Eigen::Vector3d(n01(rng), n01(rng), n01(rng));
  s.omega_radps -= s.omega_radps.dot(s.n) * s.n;
  const Eigen::Vector3d w = s.omega_radps.cross(s.n);
  const Eigen::Vector3d across = s.n.cross(w).normalized();
  switch (kind) {
    case 0: s.v_mps = 3.0 * Eigen::Vector3d(n01(rng), n01(rng), n01(rng)); break;
    case 1: s.v_mps = 3.0 * n01(rng) * s.n + 0.5 * n01(rng) * w; break;
    case 2:
      s.v_mps = 3.0 * n01(rng) * s.n + 0.5 * n01(rng) * w +
                std::pow(10.0, -3.0 + 2.5 * std::abs(n01(rng))) * across;
      break;
    case 3: s.v_mps = 0.5 * n01(rng) * w + 0.1 * n01(rng) * across; break;
    default:
      s.v_mps = 3.0 * Eigen::Vector3d(n01(rng), n01(rng), n01(rng));
      s.omega_radps.setZero();
      break;
  }
  return s;
}

double rotational_energy(const PoleState& s, const PoleParams& p) {
  return 0.5 * gs::model::pole_inertia_kgm2(p) * s.omega_radps.squaredNorm();
}

}  // namespace

TEST_CASE("eq. (10)-(15): drag matches a fine trapezoid of the printed integrals", "[pole]") {
  const PoleParams params;
  std::mt19937 rng(11);
  double worst_force = 0.0;
  double worst_torque = 0.0;
  for (int kind = 0; kind < 5; ++kind) {
    for (int i = 0; i < 60; ++i) {
      const PoleState s = random_pole_state(rng, kind);
      const PoleDrag quad = gs::model::pole_drag(s, params);
      const PoleDrag ref = trapezoid_drag(s, params, 40000);
      INFO("kind " << kind << " sample " << i);
      // The axial force may vanish (broadside flight): measure it against the total force.
      const double total = (ref.axial_force_N + ref.normal_force_N).norm();
      CHECK((quad.axial_force_N - ref.axial_force_N).norm() < 1e-9 * total);
      const double ef = relative_error(quad.normal_force_N, ref.normal_force_N);
      const double et = relative_error(quad.torque_Nm, ref.torque_Nm);
      CHECK(ef < 1e-5);
      if (kind != 4) CHECK(et < 1e-5);
      if (kind == 4) CHECK(quad.torque_Nm.norm() < 1e-14);
      worst_force = std::max(worst_force, ef);
      if (kind != 4) worst_torque = std::max(worst_torque, et);
    }
  }
  std::printf("drag quadrature vs 40000-panel trapezoid: worst relative error force %.2e, "
              "torque %.2e\n",
              worst_force, worst_torque);
}

TEST_CASE("drag closed forms: broadside translation and pure rotation", "[pole]") {
  const PoleParams params;
  PoleState s;
  s.n = Eigen::Vector3d(std::sin(0.4), 0.0, std::cos(0.4));
  const Eigen::Vector3d across(std::cos(0.4), 0.0, -std::sin(0.4));
  // Broadside at 3 m/s: F = -c_xy 2L |v| v, no torque, no axial force.
  s.v_mps = 3.0 * across;
  PoleDrag d = gs::model::pole_drag(s, params);
  CHECK((d.normal_force_N + params.drag_normal * 2.0 * kL * 3.0 * s.v_mps).norm() < 1e-15);
  CHECK(d.torque_Nm.norm() < 1e-15);
  CHECK(d.axial_force_N.norm() < 1e-15);
  // Along the axis: F_z = -c_z 2L |v| v.
  s.v_mps = -4.0 * s.n;
  d = gs::model::pole_drag(s, params);
  CHECK((d.axial_force_N + params.drag_axial * 2.0 * kL * 4.0 * s.v_mps).norm() < 1e-15);
  CHECK(d.normal_force_N.norm() < 1e-15);
  // Pure rotation about the centre: v(xi) = xi w, so F_xy = 0 and
  // M = -c_rot |w| (n x w) int xi^2 |xi| dxi = -c_rot |w| (n x w) L^4 / 2, opposing Omega.
  s.v_mps.setZero();
  s.omega_radps = Eigen::Vector3d(0.0, 2.5, 0.0);
  const Eigen::Vector3d w = s.omega_radps.cross(s.n);
  d = gs::model::pole_drag(s, params);
  const Eigen::Vector3d expected = -params.drag_rotational * w.norm() * s.n.cross(w) * std::pow(kL, 4) / 2.0;
  CHECK(relative_error(d.torque_Nm, expected) < 1e-12);
  CHECK(d.torque_Nm.dot(s.omega_radps) < 0.0);
  CHECK(d.normal_force_N.norm() < 1e-15);
}

TEST_CASE("without drag the centre flies ballistically and Omega is constant", "[pole]") {
  const PoleParams params = gs::model::without_drag(PoleParams{});
  PoleState s0;
  s0.p_m = Eigen::Vector3d(1.8, -0.2, 2.6);
  s0.v_mps = Eigen::Vector3d(1.7, 0.4, 4.7);
  s0.n = Eigen::Vector3d(0.3, 0.2, 0.9).normalized();
  s0.omega_radps = Eigen::Vector3d(0.5, 2.5, -0.3);
  s0 = gs::model::normalised_pole_state(s0);
  const double t = 1.3;
  const PoleState s = gs::model::propagate_pole(s0, t, 0.005, params);
  const Eigen::Vector3d gravity(0.0, 0.0, -kG);
  CHECK((s.p_m - (s0.p_m + s0.v_mps * t + 0.5 * gravity * t * t)).norm() < 1e-12);
  CHECK((s.v_mps - (s0.v_mps + gravity * t)).norm() < 1e-12);
  CHECK((s.omega_radps - s0.omega_radps).norm() < 1e-12);
  // n turns uniformly about Omega: Rodrigues' rotation by |Omega| t.
  const double angle = s0.omega_radps.norm() * t;
  const Eigen::Vector3d k = s0.omega_radps.normalized();
  const Eigen::Vector3d n_expected =
      s0.n * std::cos(angle) + k.cross(s0.n) * std::sin(angle) + k * k.dot(s0.n) * (1.0 - std::cos(angle));
  CHECK((s.n - n_expected).norm() < 1e-9);
  CHECK(gs::model::pole_energy_J(s, params) == Approx(gs::model::pole_energy_J(s0, params)).epsilon(1e-12));
}

TEST_CASE("with drag the total energy falls monotonically", "[pole]") {
  const PoleParams params;
  std::mt19937 rng(5);
  for (int kind = 0; kind < 5; ++kind) {
    PoleState s = gs::model::normalised_pole_state(random_pole_state(rng, kind));
    s.p_m = Eigen::Vector3d(0.0, 0.0, 3.0);
    const double e0 = gs::model::pole_energy_J(s, params);
    double previous = e0;
    bool monotonic = true;
    for (int i = 0; i < 400; ++i) {  // 2 s
      s = gs::model::pole_free_flight_step(s, 0.005, params);
      const double e = gs::model::pole_energy_J(s, params);
      if (!(e < previous)) monotonic = false;
      previous = e;
    }
    INFO("kind " << kind);
    CHECK(monotonic);
    CHECK(previous < e0 - 1e-4);
  }
}

TEST_CASE("drag slows the rotation and limits the fall to the terminal speed", "[pole]") {
  const PoleParams params;
  PoleState s;
  s.p_m = Eigen::Vector3d(0.0, 0.0, 5.0);
  s.n = Eigen::Vector3d::UnitX();
  s.omega_radps = Eigen::Vector3d(0.0, 0.0, 6.0);  // turning in the horizontal plane
  const double rotation0 = rotational_energy(s, params);
  const PoleState later = gs::model::propagate_pole(s, 1.0, 0.005, params);
  CHECK(rotational_energy(later, params) < 0.9 * rotation0);
  CHECK(std::abs(later.n.z()) < 1e-12);  // stays horizontal by symmetry
  // Falling broadside, (11) balances the weight at m_p g = c_xy 2L v^2.
  const double terminal = std::sqrt(params.mass_kg * kG / (params.drag_normal * 2.0 * kL));
  CHECK(later.v_mps.z() < 0.0);
  CHECK(later.v_mps.z() > -terminal);
  const PoleState much_later = gs::model::propagate_pole(s, 6.0, 0.005, params);
  CHECK(much_later.v_mps.z() == Approx(-terminal).epsilon(0.01));
}

TEST_CASE("the integrator keeps |n| = 1 and Omega normal to n, and is 4th order", "[pole]") {
  const PoleParams params;
  PoleState s0;
  s0.v_mps = Eigen::Vector3d(2.0, -1.0, 5.0);
  s0.n = Eigen::Vector3d(0.2, 0.5, 0.8).normalized();
  s0.omega_radps = Eigen::Vector3d(4.0, -3.0, 2.0) + 1.5 * s0.n;  // a spin to be removed
  const PoleState a = gs::model::propagate_pole(s0, 2.0, 0.01, params);
  CHECK(a.n.norm() == Approx(1.0).epsilon(1e-15));
  CHECK(std::abs(a.omega_radps.dot(a.n)) < 1e-14);
  // Halving the step shrinks the error about 16-fold against a fine reference.
  const PoleState ref = gs::model::propagate_pole(s0, 1.0, 1e-4, params);
  const double e1 = (gs::model::propagate_pole(s0, 1.0, 0.04, params).p_m - ref.p_m).norm();
  const double e2 = (gs::model::propagate_pole(s0, 1.0, 0.02, params).p_m - ref.p_m).norm();
  CHECK(e1 / e2 > 10.0);
  CHECK(e1 / e2 < 25.0);
}

TEST_CASE("end points and the lower end", "[pole]") {
  const PoleParams params;
  PoleState s;
  s.p_m = Eigen::Vector3d(1.0, 2.0, 3.0);
  s.n = Eigen::Vector3d(0.6, 0.0, 0.8);
  CHECK((gs::model::pole_tail_end_m(s, params) - (s.p_m - kL * s.n)).norm() < 1e-15);
  CHECK((gs::model::pole_head_end_m(s, params) - (s.p_m + kL * s.n)).norm() < 1e-15);
  CHECK(gs::model::pole_lower_end_m(s, params) == gs::model::pole_tail_end_m(s, params));
  s.n = -s.n;
  CHECK(gs::model::pole_lower_end_m(s, params) == gs::model::pole_head_end_m(s, params));
}
