// The 3D throw command (throw_command.hpp): the planar TV-LQR in the throw's plane, the
// balancing LQR's lateral rows across it.
#include "groundstation/planning/throw_command.hpp"

#include <catch2/catch.hpp>

#include <Eigen/Geometry>

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

TEST_CASE("a throw step flies the pole about the end it rests on, not the plate's centre",
          "[throw_command]") {
  const Setup& s = setup();
  const double L = 0.665;
  // The throw's start: the pole upright, its end resting 4 cm ahead of the plate's centre and
  // 1 cm to the side.
  const gs::model::PlanarState<double> x = s.tracker.reference().state_at(0.0);
  const Eigen::Vector3d offset(0.04, 0.01, 0.0);
  const gs::control::Pivot plate{Eigen::Vector3d(x(planar::kX), 0.0, x(planar::kZ)), Eigen::Vector3d::Zero()};
  gs::model::VehicleState vehicle;
  vehicle.p_m = plate.p_m - Eigen::Vector3d(0.0, 0.0, 0.03);
  gs::model::PoleState pole;
  pole.p_m = plate.p_m + offset + L * pole.n;
  const gs::model::PlanarState<double> none = gs::model::PlanarState<double>::Zero();
  const gs::control::ThrowFrame here{};
  const gs::planning::ThrowStep step = gs::planning::throw_step(
      s.tracker, s.balancing, 0.0, here, plate, offset, vehicle, pole, L, none, s.problem.limits);
  // Upright about its end: no tilt, and the pivot where the end is.
  CHECK(step.state(planar::kAlpha) == Approx(0.0).margin(1e-12));
  CHECK(step.state(planar::kX) == Approx(x(planar::kX) + 0.04));
  // The same as a pole resting on the centre of a plate moved to where the end is.
  const gs::control::Pivot moved{plate.p_m + offset, plate.v_mps};
  gs::model::VehicleState moved_vehicle = vehicle;
  moved_vehicle.p_m += offset;
  const gs::planning::ThrowStep centred =
      gs::planning::throw_step(s.tracker, s.balancing, 0.0, here, moved, Eigen::Vector3d::Zero(),
                               moved_vehicle, pole, L, none, s.problem.limits);
  CHECK((step.state - centred.state).norm() < 1e-12);
  CHECK(step.input.a_q_mps2 == Approx(centred.input.a_q_mps2));
  CHECK((step.input.omega_radps - centred.input.omega_radps).norm() < 1e-9);
}

TEST_CASE("a throw step does not depend on where in the arena or towards where it is flown",
          "[throw_command]") {
  const Setup& s = setup();
  const double L = 0.665;
  // The scene of the plan at 1 s in the throw's own frame (origin 0, yaw 0), a little off it.
  const gs::model::PlanarState<double> x = s.tracker.reference().state_at(1.0);
  const gs::control::Pivot plate{Eigen::Vector3d(x(planar::kX) + 0.02, 0.01, x(planar::kZ)),
                                 Eigen::Vector3d(x(planar::kVx), 0.0, x(planar::kVz))};
  gs::model::VehicleState vehicle;
  vehicle.p_m = plate.p_m - Eigen::Vector3d(0.0, 0.0, 0.03);
  vehicle.v_mps = plate.v_mps;
  vehicle.phi_rad = 0.02;
  vehicle.theta_rad = x(planar::kTheta);
  gs::model::PoleState pole;
  const double alpha = x(planar::kAlpha), alpha_dot = x(planar::kAlphaDot);
  pole.n = Eigen::Vector3d(std::sin(alpha), 0.01, std::cos(alpha)).normalized();
  pole.p_m = plate.p_m + L * pole.n;
  pole.v_mps = plate.v_mps + L * alpha_dot * Eigen::Vector3d(std::cos(alpha), 0.0, -std::sin(alpha));
  pole.omega_radps = Eigen::Vector3d(0.0, alpha_dot, 0.0);
  const Eigen::Vector3d resting(0.01, -0.005, 0.0);
  const gs::model::PlanarState<double> shift = gs::model::PlanarState<double>::Constant(0.01);
  const gs::control::ThrowFrame here{};
  const gs::planning::ThrowStep in_frame = gs::planning::throw_step(
      s.tracker, s.balancing, 1.0, here, plate, resting, vehicle, pole, L, shift, s.problem.limits);
  REQUIRE(in_frame.input.a_q_mps2 > s.problem.limits.a_q_min_mps2);
  REQUIRE(in_frame.input.a_q_mps2 < s.problem.limits.a_q_max_mps2);

  // The same scene turned by 2 rad about the vertical and moved to (3, -1, 2): the vehicle's body
  // axes are relabelled by the turn (throw_frame.hpp), so its attitude is a R a^T and the rates
  // it is commanded come out turned.
  const gs::control::ThrowFrame there{Eigen::Vector3d(3.0, -1.0, 2.0), 2.0};
  const Eigen::Matrix3d a = Eigen::AngleAxisd(there.yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Matrix3d r =
      a * gs::model::rotation_inertial_from_body(vehicle.phi_rad, vehicle.theta_rad, vehicle.psi_rad) *
      a.transpose();
  gs::model::VehicleState moved;
  moved.p_m = there.origin_m + a * vehicle.p_m;
  moved.v_mps = a * vehicle.v_mps;
  moved.theta_rad = -std::asin(r(2, 0));
  moved.phi_rad = std::atan2(r(2, 1), r(2, 2));
  moved.psi_rad = std::atan2(r(1, 0), r(0, 0));
  gs::model::PoleState moved_pole;
  moved_pole.p_m = there.origin_m + a * pole.p_m;
  moved_pole.v_mps = a * pole.v_mps;
  moved_pole.n = a * pole.n;
  moved_pole.omega_radps = a * pole.omega_radps;
  const gs::control::Pivot moved_plate{there.origin_m + a * plate.p_m, a * plate.v_mps};
  const gs::planning::ThrowStep in_arena =
      gs::planning::throw_step(s.tracker, s.balancing, 1.0, there, moved_plate, a * resting, moved,
                               moved_pole, L, shift, s.problem.limits);

  CHECK((in_arena.state - in_frame.state).norm() < 1e-9);
  CHECK(in_arena.input.a_q_mps2 == Approx(in_frame.input.a_q_mps2));
  CHECK((in_arena.input.omega_radps - a * in_frame.input.omega_radps).norm() < 1e-9);
  // The shift is the learnt throw's: the TV-LQR sees the state less the shift.
  const gs::planning::ThrowStep unshifted =
      gs::planning::throw_step(s.tracker, s.balancing, 1.0, here, plate, resting, vehicle, pole, L,
                               gs::model::PlanarState<double>::Zero(), s.problem.limits);
  CHECK(unshifted.state == in_frame.state);
  CHECK(unshifted.input.a_q_mps2 != Approx(in_frame.input.a_q_mps2));
}
