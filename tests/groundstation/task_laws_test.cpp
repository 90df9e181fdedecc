// The runtime's task laws (groundstation/control/task_laws.hpp): the carrot's speed profile,
// the position integral, the hover, balancing and release laws, the tilt limit and the input
// clamp.
#include <catch2/catch.hpp>

#include <cmath>

#include "groundstation/control/balancing_lqr.hpp"
#include "groundstation/control/hover_lqr.hpp"
#include "groundstation/control/task_laws.hpp"

namespace {

using namespace gs::control;
using gs::model::PoleState;
using gs::model::VehicleInput;
using gs::model::VehicleLimits;
using gs::model::VehicleState;

VehicleState at(const Eigen::Vector3d& p_m) {
  VehicleState s;
  s.p_m = p_m;
  return s;
}

}  // namespace

TEST_CASE("The carrot starts where the vehicle is, accelerates, cruises and stops on the target") {
  const CarrotLimits limits{1.0, 1.0};
  const double dt = 0.005;
  SetPoint sp;
  const Eigen::Vector3d start(0.0, 0.0, 1.0), target(3.0, 0.0, 1.0);
  move_set_point(sp, target, start, dt, limits);
  REQUIRE(sp.valid);
  CHECK((sp.position_m - start).norm() == Approx(dt * dt).margin(1e-12));  // one step at a dt
  double t = dt, top_speed = 0.0, last_speed = sp.velocity_mps.norm(), worst_jump = 0.0;
  while ((sp.position_m - target).norm() > 0.0 && t < 10.0) {
    move_set_point(sp, target, start, dt, limits);
    const double speed = sp.velocity_mps.norm();
    worst_jump = std::max(worst_jump, speed - last_speed);
    top_speed = std::max(top_speed, speed);
    last_speed = speed;
    t += dt;
  }
  CHECK(sp.position_m == target);
  CHECK(sp.velocity_mps.isZero());
  CHECK(top_speed == Approx(limits.speed_mps));
  CHECK(worst_jump <= limits.acceleration_mps2 * dt + 1e-12);
  // 1 s up to speed (0.5 m), 2 m at 1 m/s, 1 s of braking (0.5 m): 4 s.
  CHECK(t == Approx(4.0).margin(0.05));
  // At the target it stays there.
  move_set_point(sp, target, Eigen::Vector3d::Zero(), dt, limits);
  CHECK(sp.position_m == target);
}

TEST_CASE("The position integral runs at rest only, and is bounded") {
  SetPoint sp;
  sp.position_m = Eigen::Vector3d(0.0, 0.0, 1.0);
  sp.valid = true;
  Eigen::Vector3d integral = Eigen::Vector3d::Zero();
  const Eigen::Vector3d below(0.0, 0.0, 0.9);
  integrate_position_error(integral, sp, Eigen::Vector3d(1.0, 0.0, 1.0), below, 0.1, 1.0);
  CHECK(integral.isZero());  // the set point still moves towards its target
  integrate_position_error(integral, sp, sp.position_m, below, 0.1, 1.0);
  CHECK(integral.z() == Approx(0.01));
  for (int i = 0; i < 2000; ++i) integrate_position_error(integral, sp, sp.position_m, below, 0.1, 1.0);
  CHECK(integral.z() == 1.0);
  CHECK(integral.head<2>().isZero());
}

TEST_CASE("The hover law: gravity at the reference, more thrust below it, feed-forward passed through") {
  const LqrGain k = hover_lqr();
  REQUIRE(k.ok);
  HoverReference ref;
  ref.position_m = Eigen::Vector3d(1.0, 2.0, 1.5);
  const VehicleInput u = hover_law(k, at(ref.position_m), ref);
  CHECK(u.a_q_mps2 == Approx(pa::kGravity_mps2));
  CHECK(u.omega_radps.norm() == Approx(0.0).margin(1e-12));
  CHECK(hover_law(k, at(ref.position_m - 0.1 * Eigen::Vector3d::UnitZ()), ref).a_q_mps2 > pa::kGravity_mps2);
  // Behind the reference in x: pitch forward (a positive pitch rate tilts thrust towards +x).
  CHECK(hover_law(k, at(ref.position_m - 0.1 * Eigen::Vector3d::UnitX()), ref).omega_radps.y() > 0.0);
  // On a tilted reference with its nominal inputs, tracked exactly: the nominal inputs.
  ref.pitch_rad = 0.2;
  ref.thrust_mps2 = 11.0;
  ref.body_rates_radps = Eigen::Vector3d(0.1, -0.3, 0.0);
  VehicleState on = at(ref.position_m);
  on.theta_rad = 0.2;
  const VehicleInput ff = hover_law(k, on, ref);
  CHECK(ff.a_q_mps2 == Approx(11.0));
  CHECK((ff.omega_radps - ref.body_rates_radps).norm() == Approx(0.0).margin(1e-12));
}

TEST_CASE("The balancing law holds an upright pole at its set point with its weight as feed-forward") {
  const LqrGain k = balancing_lqr();
  REQUIRE(k.ok);
  const double L = 0.665;
  const Eigen::Vector3d pivot_m(0.0, 0.0, 2.0);
  PoleState pole;
  pole.p_m = pivot_m + L * Eigen::Vector3d::UnitZ();
  const VehicleState vehicle = at(pivot_m - Eigen::Vector3d(0.0, 0.0, 0.03));
  const VehicleInput u = balance_law(k, Pivot{pivot_m, Eigen::Vector3d::Zero()}, vehicle, pole, L, pivot_m,
                                     Eigen::Vector3d::Zero(), 0.5);
  CHECK(u.a_q_mps2 == Approx(pa::kGravity_mps2 + 0.5));
  CHECK(u.omega_radps.norm() == Approx(0.0).margin(1e-9));
  // The pole leaning towards +x: the plate moves under it (pitch towards +x).
  pole.n = Eigen::Vector3d(0.05, 0.0, 1.0).normalized();
  pole.p_m = pivot_m + L * pole.n;
  CHECK(balance_law(k, Pivot{pivot_m, Eigen::Vector3d::Zero()}, vehicle, pole, L, pivot_m,
                    Eigen::Vector3d::Zero(), 0.5)
            .omega_radps.y() > 0.0);
}

TEST_CASE("The release pitches back first, then levels") {
  VehicleState s;
  s.phi_rad = 0.1;
  s.theta_rad = -0.2;
  const Eigen::Vector3d back(0.0, 2.5, 0.0);
  const VehicleInput first = release_law(s, 0.05, 0.1, back, 8.0, 1.0);
  CHECK(first.a_q_mps2 == 1.0);
  CHECK(first.omega_radps == back);
  const VehicleInput then = release_law(s, 0.1, 0.1, back, 8.0, 1.0);
  CHECK(then.omega_radps.x() == Approx(-0.8));
  CHECK(then.omega_radps.y() == Approx(1.6));
  CHECK(then.omega_radps.z() == 0.0);
}

TEST_CASE("The tilt limit bounds the rates towards it, and brings a vehicle beyond it back") {
  const TiltLimit limit{0.7, 10.0};
  VehicleInput u;
  u.a_q_mps2 = 12.0;
  u.omega_radps = Eigen::Vector3d(3.0, -2.0, 0.5);
  VehicleState s;
  CHECK(limit_tilt(u, s, limit).omega_radps == u.omega_radps);  // level: up to 7 rad/s pass
  s.phi_rad = 0.5;     // 3 rad/s rolling on towards the limit: at most 10 (0.7 - 0.5) = 2
  s.theta_rad = -0.6;  // -2 rad/s pitching on towards it: at least -10 (0.7 - 0.6) = -1
  VehicleInput limited = limit_tilt(u, s, limit);
  CHECK(limited.omega_radps.x() == Approx(2.0));
  CHECK(limited.omega_radps.y() == Approx(-1.0));
  CHECK(limited.omega_radps.z() == 0.5);
  CHECK(limited.a_q_mps2 == 12.0);
  s.phi_rad = 0.8;  // beyond: brought back at 1 rad/s at least
  s.theta_rad = 0.0;
  limited = limit_tilt(u, s, limit);
  CHECK(limited.omega_radps.x() == Approx(-1.0));
  CHECK(limited.omega_radps.y() == -2.0);
  // Rates away from the limit pass.
  u.omega_radps = Eigen::Vector3d(-5.0, 4.0, 0.0);
  s.phi_rad = 0.5;
  s.theta_rad = -0.6;
  CHECK(limit_tilt(u, s, limit).omega_radps == u.omega_radps);
}

TEST_CASE("The clamp keeps thrust and each body rate within the vehicle's limits") {
  const VehicleLimits limits{1.0, 20.0, 10.0};
  VehicleInput u;
  u.a_q_mps2 = 25.0;
  u.omega_radps = Eigen::Vector3d(-12.0, 3.0, 11.0);
  const VehicleInput c = clamp_input(u, limits);
  CHECK(c.a_q_mps2 == 20.0);
  CHECK(c.omega_radps == Eigen::Vector3d(-10.0, 3.0, 10.0));
  u.a_q_mps2 = 0.0;
  CHECK(clamp_input(u, limits).a_q_mps2 == 1.0);
}
