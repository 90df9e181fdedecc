// The optimal catching instant (Section III-B): the first instant of the free flight satisfying
// (42), the nominal catching height and catch point; the swing-up it promises; the launch state
// from the throw planner's CSV.
#include "groundstation/planning/catching_instant.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <string>

#include "groundstation/model/impact.hpp"
#include "groundstation/model/pole_on_vehicle.hpp"
#include "groundstation/model/rk4.hpp"

namespace {

using gs::model::PoleParams;
using gs::model::PoleState;
using gs::planning::CatchingInstant;

constexpr double kL = pa::kPoleHalfLength_m;
constexpr double kG = pa::kGravity_mps2;

PoleState fig5_launch(const PoleParams& params) {
  return gs::planning::pole_state_at_launch(gs::planning::fig5_launch_state(), params);
}

// Drag-free flight in closed form: ballistic centre, n turning uniformly about the constant Omega.
PoleState ballistic(const PoleState& s0, double t) {
  PoleState s = s0;
  s.p_m = s0.p_m + s0.v_mps * t + 0.5 * Eigen::Vector3d(0, 0, -kG) * t * t;
  s.v_mps = s0.v_mps + Eigen::Vector3d(0, 0, -kG) * t;
  const double angle = s0.omega_radps.norm() * t;
  const Eigen::Vector3d k = s0.omega_radps.normalized();
  s.n = s0.n * std::cos(angle) + k.cross(s0.n) * std::sin(angle) + k * k.dot(s0.n) * (1.0 - std::cos(angle));
  return s;
}

// The pivoted rod after a catch by a vehicle at rest (eq. 28, 29 with a still pivot).
struct SwingOutcome {
  double min_tilt_rad;
  bool crossed;
};
SwingOutcome swing(const gs::model::PoleOnVehicleState& start, const PoleParams& params) {
  gs::model::PoleOnVehicleState s = start;
  const Eigen::Vector3d still = Eigen::Vector3d::Zero();
  const auto f = [&](const gs::model::PoleOnVehicleState& x) {
    return gs::model::pole_on_vehicle_derivative(x, still, params);
  };
  SwingOutcome out{std::asin(std::abs(s.a_m) / kL), false};
  const double sign0 = s.a_m > 0 ? 1.0 : -1.0;
  // 2 s: on the separatrix the pole approaches the upright for ever, but any residual error grows
  // like exp(t sqrt(3g / 4L)) (time constant 0.3 s); the on-time catch stays up beyond 3 s.
  for (int i = 0; i < 2000; ++i) {
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

TEST_CASE("launch state: eq. (23), (26), (27) from the planar throw end", "[catching_instant]") {
  const PoleParams params;
  const gs::planning::PlanarLaunchState launch = gs::planning::fig5_launch_state();
  const PoleState s = gs::planning::pole_state_at_launch(launch, params);
  gs::model::PoleOnVehicleState on{kL * std::sin(launch.alpha_rad), 0.0,
                                   kL * std::cos(launch.alpha_rad) * launch.alpha_dot_radps, 0.0};
  const PoleState expected = gs::model::free_flight_state_from_pole_on_vehicle(
      on, {launch.x_m, 0.0, launch.z_m}, {launch.vx_mps, 0.0, launch.vz_mps}, params);
  CHECK((s.p_m - expected.p_m).norm() < 1e-14);
  CHECK((s.v_mps - expected.v_mps).norm() < 1e-14);
  CHECK((s.n - expected.n).norm() < 1e-14);
  CHECK((s.omega_radps - expected.omega_radps).norm() < 1e-14);
  // The tail (lower) end is the throwing vehicle's centre.
  CHECK((gs::model::pole_tail_end_m(s, params) - Eigen::Vector3d(1.5, 0.0, 2.0)).norm() < 1e-14);
}

TEST_CASE("Fig. 5 launch: the first instant satisfying (42)", "[catching_instant]") {
  const PoleParams params;
  const PoleState launch = fig5_launch(params);
  const CatchingInstant ci = gs::planning::find_catching_instant(launch, params);
  REQUIRE(ci.found);
  std::printf("catching instant (Fig. 5 launch, drag): t = %.4f s, height %.4f m, point (%.4f, %.4f) m"
              " [paper, measured: 0.812 s, 1.343 m]\n",
              ci.t_s, ci.catch_height_m, ci.catch_point_m.x(), ci.catch_point_m.y());
  CHECK(ci.t_s > 0.0);
  CHECK(std::abs(ci.residual_radps) < 1e-6);
  CHECK(std::abs(gs::model::catching_condition_residual_radps(ci.pole, params)) < 1e-6);
  // Consistent with an independent integration to t*.
  const PoleState at = gs::model::propagate_pole(launch, ci.t_s, 1e-3, params);
  const Eigen::Vector3d lower = gs::model::pole_lower_end_m(at, params);
  CHECK(lower.z() == Approx(ci.catch_height_m).margin(1e-6));
  CHECK(lower.x() == Approx(ci.catch_point_m.x()).margin(1e-6));
  CHECK(std::abs(lower.y()) < 1e-12);
  CHECK(std::abs(ci.catch_point_m.y()) < 1e-12);
  // The first: on a 1 ms grid, no sign change of (42) before t* except where the lower end
  // switches (alpha jumps by pi there; not a root).
  PoleState s = launch;
  double previous = gs::model::catching_condition_residual_radps(s, params);
  bool previous_head = s.n.z() < 0.0;
  int genuine_sign_changes = 0;
  int end_switches = 0;
  const int samples = static_cast<int>(std::floor(ci.t_s / 1e-3)) - 1;
  for (int i = 0; i < samples; ++i) {
    s = gs::model::pole_free_flight_step(s, 1e-3, params);
    const double r = gs::model::catching_condition_residual_radps(s, params);
    const bool head = s.n.z() < 0.0;
    if (head != previous_head) {
      ++end_switches;
    } else if ((r > 0) != (previous > 0)) {
      ++genuine_sign_changes;
    }
    previous = r;
    previous_head = head;
  }
  CHECK(genuine_sign_changes == 0);
  CHECK(end_switches == 1);  // the Fig. 5 pole turns over once: the catch is on its other end
  // And just after t*, the residual has changed sign.
  const double before = gs::model::catching_condition_residual_radps(
      gs::model::propagate_pole(launch, ci.t_s - 2e-3, 1e-3, params), params);
  const double after = gs::model::catching_condition_residual_radps(
      gs::model::propagate_pole(launch, ci.t_s + 2e-3, 1e-3, params), params);
  CHECK(before * after < 0.0);
}

// (42) is planar; a throw in another direction is the same throw turned about the vertical and
// must meet it at the same instant and height, at the turned point (with the xz-plane's (42) a
// throw along y had no root before the floor).
TEST_CASE("the catching instant of a throw turned about the vertical is the same instant, turned",
          "[catching_instant]") {
  const PoleParams params;
  const PoleState launch = fig5_launch(params);
  const CatchingInstant straight = gs::planning::find_catching_instant(launch, params);
  REQUIRE(straight.found);
  for (double yaw_deg : {30.0, 90.0, 126.0, 180.0, 270.0, -45.0}) {
    INFO("yaw " << yaw_deg << " deg");
    const double yaw = yaw_deg * M_PI / 180.0;
    const Eigen::Matrix3d turn = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    const PoleState turned{turn * launch.p_m, turn * launch.v_mps, turn * launch.n,
                           turn * launch.omega_radps};
    CHECK(gs::model::flight_plane_yaw_rad(turned) == Approx(std::remainder(yaw, 2.0 * M_PI)).margin(1e-12));
    const CatchingInstant ci = gs::planning::find_catching_instant(turned, params);
    REQUIRE(ci.found);
    CHECK(ci.t_s == Approx(straight.t_s).margin(1e-9));
    CHECK(ci.catch_height_m == Approx(straight.catch_height_m).margin(1e-9));
    CHECK((ci.catch_point_m - turn.topLeftCorner<2, 2>() * straight.catch_point_m).norm() < 1e-9);
    CHECK(std::abs(ci.residual_radps) < 1e-6);
  }
}

TEST_CASE("without drag the catching instant matches the ballistic closed form", "[catching_instant]") {
  const PoleParams params = gs::model::without_drag(PoleParams{});
  const PoleState launch = fig5_launch(params);
  const CatchingInstant ci = gs::planning::find_catching_instant(launch, params);
  REQUIRE(ci.found);
  const PoleState exact = ballistic(launch, ci.t_s);
  CHECK((ci.pole.p_m - exact.p_m).norm() < 1e-9);
  CHECK((ci.pole.v_mps - exact.v_mps).norm() < 1e-9);
  CHECK((ci.pole.n - exact.n).norm() < 1e-9);
  // An independent root of (42) on the closed-form flight, after the pole has turned over.
  const auto residual = [&](double t) {
    return gs::model::catching_condition_residual_radps(ballistic(launch, t), params);
  };
  double t = 0.0;
  while (ballistic(launch, t).n.z() > 0.0) t += 1e-3;  // past the horizontal
  double lo = t;
  while (residual(t + 1e-3) * residual(lo) > 0.0) t += 1e-3;
  double hi = t + 1e-3;
  lo = t;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    ((residual(mid) > 0) == (residual(lo) > 0) ? lo : hi) = mid;
  }
  CHECK(ci.t_s == Approx(0.5 * (lo + hi)).margin(1e-8));
  const Eigen::Vector3d lower = gs::model::pole_lower_end_m(exact, params);
  CHECK(ci.catch_height_m == Approx(lower.z()).margin(1e-8));
  CHECK(ci.catch_point_m.x() == Approx(lower.x()).margin(1e-8));
  std::printf("catching instant (Fig. 5 launch, no drag): t = %.4f s, height %.4f m, x %.4f m\n", ci.t_s,
              ci.catch_height_m, ci.catch_point_m.x());
}

TEST_CASE("caught at t* by a vehicle at rest the pole swings up; earlier or later it does not",
          "[catching_instant]") {
  const PoleParams params;
  const PoleState launch = fig5_launch(params);
  const CatchingInstant ci = gs::planning::find_catching_instant(launch, params);
  REQUIRE(ci.found);
  const double one_degree = M_PI / 180.0;
  const auto catch_at = [&](double t) {
    const PoleState before = gs::model::propagate_pole(launch, t, 1e-3, params);
    return swing(gs::model::impact_map(before, Eigen::Vector3d::Zero(), params).on_vehicle, params);
  };
  const SwingOutcome on_time = catch_at(ci.t_s);
  CHECK(on_time.min_tilt_rad < one_degree);
  CHECK_FALSE(on_time.crossed);
  // 30 ms early the pole has too little energy and falls back; 30 ms late too much, and it
  // falls over the top.
  const SwingOutcome early = catch_at(ci.t_s - 0.03);
  CHECK_FALSE(early.crossed);
  CHECK(early.min_tilt_rad > 5.0 * one_degree);
  const SwingOutcome late = catch_at(ci.t_s + 0.03);
  CHECK(late.crossed);
}

TEST_CASE("no instant within the horizon: not found", "[catching_instant]") {
  const PoleParams params;
  gs::planning::CatchingInstantOptions options;
  options.horizon_s = 0.3;  // the Fig. 5 pole has not turned over yet
  CHECK_FALSE(gs::planning::find_catching_instant(fig5_launch(params), params, options).found);
  options.horizon_s = -1.0;
  CHECK_FALSE(gs::planning::find_catching_instant(fig5_launch(params), params, options).found);
}

TEST_CASE("launch state from the throw planner's CSV", "[catching_instant]") {
  const std::string header = "t,x,z,vx,vz,theta,alpha,alpha_dot,a_q,omega_y,F_N\n";
  const std::string good = header + "0,0,0,0,0,0,0,0,9.81,0,9.81\n"
                                    "2.5,1.5,2.0,0.3,5.5,-0.48,0.48,2.5,4.48,2.5,0\n"
                                    "\n";
  const auto ok = gs::planning::parse_throw_csv_launch_state(good, "throw.csv");
  INFO(ok.error);
  REQUIRE(ok.ok);
  CHECK(ok.line == 3);
  CHECK(ok.launch.x_m == 1.5);
  CHECK(ok.launch.z_m == 2.0);
  CHECK(ok.launch.vx_mps == 0.3);
  CHECK(ok.launch.vz_mps == 5.5);
  CHECK(ok.launch.alpha_rad == 0.48);
  CHECK(ok.launch.alpha_dot_radps == 2.5);
  // Columns in another order, CRLF line ends.
  const auto reordered = gs::planning::parse_throw_csv_launch_state(
      "alpha_dot,alpha,F_N,omega_y,a_q,theta,vz,vx,z,x,t\r\n2.5,0.48,0,2.5,4.48,-0.48,5.5,0.3,2,1.5,2.5\r\n",
      "r.csv");
  REQUIRE(reordered.ok);
  CHECK(reordered.launch.x_m == 1.5);
  CHECK(reordered.launch.alpha_dot_radps == 2.5);

  struct Case {
    std::string text;
    std::string expect;
  };
  const Case bad[] = {
      {"", "throw.csv: empty file"},
      {header, "throw.csv:1: no data rows"},
      {"t,x,z,vx,vz,theta,alpha,a_q,omega_y,F_N\n1,2,3,4,5,6,7,8,9,10\n",
       "throw.csv:1: header lacks column `alpha_dot`"},
      {"t,x,x,z,vx,vz,theta,alpha,alpha_dot,a_q,omega_y,F_N\n", "throw.csv:1: duplicate column `x`"},
      {header + "0,0,0,0,0,0,0,0,9.81,0,9.81\n1,2,3\n", "throw.csv:3: expected 11 fields, got 3"},
      {header + "0,0,0,0,0,0,0,zero,9.81,0,9.81\n", "throw.csv:2: field 8 is not a finite number"},
      {header + "0,0,0,0,0,0,0,nan,9.81,0,9.81\n", "throw.csv:2: field 8"},
      {header + "0,0,0,0,0,0,0,,9.81,0,9.81\n", "throw.csv:2: field 8"},
  };
  for (const Case& c : bad) {
    const auto r = gs::planning::parse_throw_csv_launch_state(c.text, "throw.csv");
    INFO(c.text << " -> " << r.error);
    CHECK_FALSE(r.ok);
    CHECK(r.error.find(c.expect) != std::string::npos);
  }
  const auto missing = gs::planning::load_throw_csv_launch_state("/nonexistent/throw.csv");
  CHECK_FALSE(missing.ok);
  CHECK(missing.error.find("/nonexistent/throw.csv") != std::string::npos);
}
