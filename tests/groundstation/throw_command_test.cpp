// The 3D throw command (throw_command.hpp): the planar TV-LQR in the throw's plane, the
// balancing LQR's lateral rows across it.
#include "groundstation/planning/throw_command.hpp"

#include <catch2/catch.hpp>

#include "groundstation/control/balancing_lqr.hpp"
#include "groundstation/planning/throw_planner.hpp"

namespace {

namespace bal = gs::control::balancing;
namespace planar = gs::model::planar;
using gs::planning::ThrowProblem;

struct Setup {
  ThrowProblem problem;
  gs::planning::ThrowTracker tracker{gs::planning::plan_throw(ThrowProblem{}).trajectory};
  gs::control::LqrGain balancing = gs::control::balancing_lqr();
};

const Setup& setup() {
  static const Setup s;
  return s;
}

// A planar state off the plan at t, and the matching in-plane part of s_qp.
gs::model::PlanarState<double> off_plan(const Setup& s, double t) {
  gs::model::PlanarState<double> x = s.tracker.reference().state_at(t);
  x(planar::kX) += 0.03;
  x(planar::kAlpha) += 0.01;
  return x;
}

}  // namespace

TEST_CASE("in the throw's plane the command is the planar TV-LQR's, saturated", "[throw_command]") {
  const Setup& s = setup();
  REQUIRE(s.tracker.valid());
  REQUIRE(s.balancing.ok);
  for (double t : {0.0, 1.0, 2.0, 2.45}) {
    const gs::model::PlanarState<double> x = off_plan(s, t);
    Eigen::VectorXd sqp = Eigen::VectorXd::Zero(bal::kStateSize);
    sqp(bal::kX) = x(planar::kX);  // in-plane parts of s_qp do not reach the lateral rows
    sqp(bal::kPitch) = x(planar::kTheta);
    sqp(bal::kA) = 0.4;
    const gs::model::VehicleInput u =
        gs::planning::throw_command(s.tracker, s.balancing, t, x, sqp, s.problem.limits);
    const gs::model::PlanarInput<double> expected =
        gs::planning::saturate(s.tracker.command(t, x), s.problem.limits);
    CHECK(u.a_q_mps2 == expected(planar::kThrust));
    CHECK(u.omega_radps.y() == expected(planar::kPitchRate));
    CHECK(u.omega_radps.x() == 0.0);
    CHECK(u.omega_radps.z() == 0.0);
  }
}

TEST_CASE("across the plane the pole is balanced by the balancing LQR's lateral rows", "[throw_command]") {
  const Setup& s = setup();
  const double t = 2.0;
  const gs::model::PlanarState<double> x = off_plan(s, t);
  Eigen::VectorXd lateral = Eigen::VectorXd::Zero(bal::kStateSize);
  lateral(bal::kY) = 0.02;
  lateral(bal::kRoll) = 0.01;
  lateral(bal::kYaw) = 0.05;
  lateral(bal::kB) = 0.01;
  lateral(bal::kBDot) = 0.02;
  const gs::model::VehicleInput u =
      gs::planning::throw_command(s.tracker, s.balancing, t, x, lateral, s.problem.limits);
  const Eigen::VectorXd hover = -s.balancing.K * lateral;
  CHECK(u.omega_radps.x() == Approx(hover(bal::kRateX)));
  CHECK(u.omega_radps.z() == Approx(hover(bal::kRateZ)));
  // ... and the plane's inputs do not see it.
  const gs::model::PlanarInput<double> planar_only =
      gs::planning::saturate(s.tracker.command(t, x), s.problem.limits);
  CHECK(u.a_q_mps2 == planar_only(planar::kThrust));
  CHECK(u.omega_radps.y() == planar_only(planar::kPitchRate));

  // A pole leaning towards +y (b > 0) is caught by rolling the pivot under it: b'' = (3g / 4L) b
  // + (3g / 4) phi (balancing_lqr.hpp), so the roll must go negative.
  Eigen::VectorXd leaning = Eigen::VectorXd::Zero(bal::kStateSize);
  leaning(bal::kB) = 0.02;
  CHECK(gs::planning::throw_command(s.tracker, s.balancing, t, x, leaning, s.problem.limits).omega_radps.x() <
        0.0);
}

TEST_CASE("the lateral rates are clamped into the rate limit", "[throw_command]") {
  const Setup& s = setup();
  Eigen::VectorXd fallen = Eigen::VectorXd::Zero(bal::kStateSize);
  fallen(bal::kB) = 0.6;
  fallen(bal::kBDot) = 5.0;
  fallen(bal::kYaw) = -3.0;
  const gs::model::VehicleInput u =
      gs::planning::throw_command(s.tracker, s.balancing, 1.0, off_plan(s, 1.0), fallen, s.problem.limits);
  CHECK(std::abs(u.omega_radps.x()) == Approx(s.problem.limits.omega_max_radps));
  CHECK(std::abs(u.omega_radps.z()) <= s.problem.limits.omega_max_radps);
  CHECK(gs::planning::lateral_balancing_state(fallen) == fallen);
}
