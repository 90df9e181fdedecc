// The catch: impact map (35)-(40) in 3D and in the plane, the energy (41) and this project's
// form of the catching condition (42) (sign convention in model/impact.hpp).
#include "groundstation/model/impact.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "groundstation/model/rk4.hpp"

namespace {

using gs::model::PoleParams;
using gs::model::PoleState;

constexpr double kL = pa::kPoleHalfLength_m;
constexpr double kG = pa::kGravity_mps2;

PoleState random_flying_pole(std::mt19937& rng) {
  std::normal_distribution<double> n01;
  PoleState s;
  s.p_m = Eigen::Vector3d(n01(rng), n01(rng), 2.0 + n01(rng));
  s.v_mps = 3.0 * Eigen::Vector3d(n01(rng), n01(rng), n01(rng));
  s.n = Eigen::Vector3d(n01(rng), n01(rng), n01(rng)).normalized();
  s.omega_radps = 3.0 * Eigen::Vector3d(n01(rng), n01(rng), n01(rng));
  return gs::model::normalised_pole_state(s);
}

// A planar pole whose lower end is the tail, with tilt alpha (|alpha| < pi/2), rate alpha_dot and
// centre velocity (x', z').
PoleState planar_pole(double alpha, double alpha_dot, double x_dot, double z_dot) {
  PoleState s;
  s.n = Eigen::Vector3d(std::sin(alpha), 0.0, std::cos(alpha));
  s.p_m = Eigen::Vector3d(0.0, 0.0, 1.5) + kL * s.n;
  s.v_mps = Eigen::Vector3d(x_dot, 0.0, z_dot);
  s.omega_radps = Eigen::Vector3d(0.0, alpha_dot, 0.0);
  return s;
}

// The pre-impact vertical centre velocity that satisfies this project's (42) for the rest.
double z_dot_on_condition(double alpha, double alpha_dot, double x_dot) {
  return (alpha_dot + 3.0 / kL * x_dot * std::cos(alpha) +
          4.0 * std::sqrt(3.0 * kG / kL) * std::sin(0.5 * alpha)) *
         kL / (3.0 * std::sin(alpha));
}

}  // namespace

TEST_CASE("3D impact: angular momentum about the contact point is conserved", "[impact]") {
  const PoleParams params;
  std::mt19937 rng(17);
  std::normal_distribution<double> n01;
  for (int i = 0; i < 200; ++i) {
    const PoleState before = random_flying_pole(rng);
    const Eigen::Vector3d plate_v = 1.5 * Eigen::Vector3d(n01(rng), n01(rng), n01(rng));
    const gs::model::ImpactResult r = gs::model::impact_map(before, plate_v, params);
    INFO("sample " << i);
    // The contact point is the lower end.
    CHECK((r.contact_point_m - gs::model::pole_lower_end_m(before, params)).norm() < 1e-14);
    CHECK(r.after.n.z() >= 0.0);
    const Eigen::Vector3d h_before =
        gs::model::pole_angular_momentum_about(before, r.contact_point_m, params);
    const Eigen::Vector3d h_after =
        gs::model::pole_angular_momentum_about(r.after, r.contact_point_m, params);
    CHECK((h_after - h_before).norm() < 1e-14);
    // Inelastic with sticking: the contact point moves with the plate afterwards (38), (39).
    const Eigen::Vector3d contact_v =
        r.after.v_mps + r.after.omega_radps.cross(r.contact_point_m - r.after.p_m);
    CHECK((contact_v - plate_v).norm() < 1e-12);
    // (35), (36): the impulse is the momentum change; (37): it turns the pole about its centre.
    CHECK((r.impulse_Ns - params.mass_kg * (r.after.v_mps - before.v_mps)).norm() < 1e-15);
    const Eigen::Vector3d spin_change =
        gs::model::pole_inertia_kgm2(params) * (r.after.omega_radps - before.omega_radps);
    CHECK((spin_change - (r.contact_point_m - before.p_m).cross(r.impulse_Ns)).norm() < 1e-15);
    // The position does not jump, and the pole-on-vehicle state describes the same motion.
    CHECK((r.after.p_m - before.p_m).norm() < 1e-15);
    const PoleState again =
        gs::model::free_flight_state_from_pole_on_vehicle(r.on_vehicle, r.contact_point_m, plate_v, params);
    // (24), (26) lose digits as the pole nears the horizontal (c' = -(a a' + b b') / c).
    CHECK((again.v_mps - r.after.v_mps).norm() < 1e-9);
    CHECK((again.p_m - r.after.p_m).norm() < 1e-12);
    // An inelastic impact dissipates energy (relative to the plate's frame).
    PoleState rel_before = before;
    PoleState rel_after = r.after;
    rel_before.v_mps -= plate_v;
    rel_after.v_mps -= plate_v;
    CHECK(gs::model::pole_energy_J(rel_after, params) <=
          gs::model::pole_energy_J(rel_before, params) + 1e-15);
  }
}

TEST_CASE("planar impact on a plate at rest is eq. (40)", "[impact]") {
  const PoleParams params;
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 100; ++i) {
    const double alpha = 1.4 * u(rng), alpha_dot = 4 * u(rng), x_dot = 3 * u(rng), z_dot = 5 * u(rng);
    const PoleState before = planar_pole(alpha, alpha_dot, x_dot, z_dot);
    const auto r = gs::model::impact_map(before, Eigen::Vector3d::Zero(), params);
    const double expected =
        0.25 * alpha_dot + 0.75 / kL * (x_dot * std::cos(alpha) - z_dot * std::sin(alpha));
    CHECK(r.after.omega_radps.y() == Approx(expected).margin(1e-12));
    CHECK(r.after.omega_radps.x() == Approx(0.0).margin(1e-15));
    CHECK(r.after.omega_radps.z() == Approx(0.0).margin(1e-15));
    // (38), (39)
    CHECK(r.after.v_mps.x() == Approx(expected * kL * std::cos(alpha)).margin(1e-12));
    CHECK(r.after.v_mps.z() == Approx(-expected * kL * std::sin(alpha)).margin(1e-12));
    const auto k = gs::model::planar_kinematics_from_lower_end(before);
    CHECK(k.alpha_rad == Approx(alpha));
    CHECK(gs::model::post_impact_rate_radps(k, params) == Approx(expected).margin(1e-12));
  }
}

TEST_CASE("the lower end is the contact end whichever way n points", "[impact]") {
  const PoleParams params;
  const PoleState up = planar_pole(-0.4, 1.5, 0.5, -3.0);
  PoleState down = up;
  down.n = -up.n;  // same body, n from the upper end
  const auto k_up = gs::model::planar_kinematics_from_lower_end(up);
  const auto k_down = gs::model::planar_kinematics_from_lower_end(down);
  CHECK(k_down.alpha_rad == Approx(k_up.alpha_rad));
  CHECK(k_down.alpha_dot_radps == Approx(k_up.alpha_dot_radps));
  CHECK(gs::model::planar_kinematics(down).alpha_rad == Approx(-0.4 + M_PI));
  const auto a = gs::model::impact_map(up, Eigen::Vector3d::Zero(), params);
  const auto b = gs::model::impact_map(down, Eigen::Vector3d::Zero(), params);
  CHECK((a.after.omega_radps - b.after.omega_radps).norm() < 1e-15);
  CHECK((a.contact_point_m - b.contact_point_m).norm() < 1e-15);
}

TEST_CASE("eq. (41): the pivoted pole's energy and the swing-up separatrix", "[impact]") {
  const PoleParams params;
  CHECK(gs::model::upright_energy_J(params) == Approx(params.mass_kg * kG * kL));
  for (double alpha : {-1.2, -0.5, -0.1, 0.2, 0.9}) {
    const double rate = gs::model::swing_up_rate_radps(alpha, params);
    // On the separatrix the energy is E* and the pole turns towards the upright.
    CHECK(gs::model::pivoted_pole_energy_J(alpha, rate, params) ==
          Approx(gs::model::upright_energy_J(params)).epsilon(1e-14));
    CHECK(rate * alpha < 0.0);
    // (41) is the pole-on-vehicle energy for a pivot at rest at z = 0.
    const gs::model::PoleOnVehicleState s{kL * std::sin(alpha), 0.0, kL * std::cos(alpha) * 0.7, 0.0};
    CHECK(gs::model::pivoted_pole_energy_J(alpha, 0.7, params) ==
          Approx(gs::model::pole_on_vehicle_energy_J(s, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                                                     params))
              .epsilon(1e-14));
  }
}

TEST_CASE("eq. (42): zero residual <=> post-impact energy E* turning upright", "[impact]") {
  const PoleParams params;
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 100; ++i) {
    double alpha = 1.2 * u(rng);
    if (std::abs(alpha) < 0.05) alpha = 0.3;
    const double alpha_dot = 3 * u(rng), x_dot = 2 * u(rng);
    const double z_dot = z_dot_on_condition(alpha, alpha_dot, x_dot);
    const PoleState on = planar_pole(alpha, alpha_dot, x_dot, z_dot);
    CHECK(gs::model::catching_condition_residual_radps(on, params) == Approx(0.0).margin(1e-10));
    const auto r = gs::model::impact_map(on, Eigen::Vector3d::Zero(), params);
    const double rate = r.after.omega_radps.y();
    CHECK(gs::model::pivoted_pole_energy_J(alpha, rate, params) ==
          Approx(gs::model::upright_energy_J(params)).epsilon(1e-10));
    CHECK(rate * alpha < 0.0);
    // Its sgn(alpha) multiple is the printed form with the middle term's sign following alpha;
    // for alpha < 0 that is the printed (42) exactly.
    const PoleState off = planar_pole(alpha, alpha_dot, x_dot, z_dot + 0.7);
    const auto k = gs::model::planar_kinematics_from_lower_end(off);
    const double sgn = alpha > 0 ? 1.0 : -1.0;
    const double bracket = k.x_dot_mps * std::cos(alpha) - k.z_dot_mps * std::sin(alpha);
    const double root = std::sqrt(24.0 * kG * (1.0 - std::cos(alpha)) / kL);
    const double residual = gs::model::catching_condition_residual_radps(off, params);
    CHECK(sgn * residual == Approx(k.alpha_dot_radps * sgn + sgn * 3.0 / kL * bracket + root).margin(1e-10));
    if (alpha < 0.0) {
      const double printed = k.alpha_dot_radps * sgn - 3.0 / kL * bracket + root;
      CHECK(sgn * residual == Approx(printed).margin(1e-10));
    }
  }
}

namespace {

struct SwingOutcome {
  double min_tilt_rad;  // closest approach to the upright
  bool crossed;         // passed through the upright (fell over)
};

// The pivoted rod after a catch by a vehicle at rest: eq. (28), (29) with a still pivot, until
// t_end or until it lies 80 deg down.
SwingOutcome swing(const gs::model::PoleOnVehicleState& start, double t_end, const PoleParams& params) {
  gs::model::PoleOnVehicleState s = start;
  const Eigen::Vector3d still = Eigen::Vector3d::Zero();
  const auto f = [&](const gs::model::PoleOnVehicleState& x) {
    return gs::model::pole_on_vehicle_derivative(x, still, params);
  };
  SwingOutcome out{std::asin(std::abs(s.a_m) / kL), false};
  const double sign0 = s.a_m > 0 ? 1.0 : -1.0;
  for (double t = 0.0; t < t_end; t += 1e-3) {
    s = gs::model::rk4_step(f, s, 1e-3);
    const double tilt = std::asin(std::min(1.0, std::abs(s.a_m) / kL));
    out.min_tilt_rad = std::min(out.min_tilt_rad, tilt);
    if (s.a_m * sign0 < 0.0) {
      out.crossed = true;
      break;
    }
    if (tilt > 80.0 * M_PI / 180.0) break;
  }
  return out;
}

}  // namespace

TEST_CASE("a pole caught on condition (42) swings up; off it, it does not", "[impact]") {
  const PoleParams params;
  const double one_degree = M_PI / 180.0;
  for (double alpha : {-0.6, -0.3, 0.45}) {
    const double alpha_dot = alpha < 0 ? 1.6 : -1.0;
    const double x_dot = 0.4;
    const double z_dot = z_dot_on_condition(alpha, alpha_dot, x_dot);
    INFO("alpha " << alpha);
    const auto on =
        gs::model::impact_map(planar_pole(alpha, alpha_dot, x_dot, z_dot), Eigen::Vector3d::Zero(), params);
    const SwingOutcome settled = swing(on.on_vehicle, 2.0, params);
    CHECK(settled.min_tilt_rad < one_degree);
    CHECK_FALSE(settled.crossed);
    for (double dz : {-0.3, 0.3}) {
      const auto off = gs::model::impact_map(planar_pole(alpha, alpha_dot, x_dot, z_dot + dz),
                                             Eigen::Vector3d::Zero(), params);
      const SwingOutcome o = swing(off.on_vehicle, 2.0, params);
      INFO("dz " << dz);
      CHECK((o.crossed || o.min_tilt_rad > one_degree));
    }
  }
}
