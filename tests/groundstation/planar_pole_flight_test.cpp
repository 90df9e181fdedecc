// The pole's planar free flight (planar_pole_flight.hpp), the target throw's differentiable model,
// against the 3D model of eq. (20) with drag (pole_free_flight.hpp) that the ground station flies
// by.
#include "groundstation/model/planar_pole_flight.hpp"

#include <catch2/catch.hpp>
#include <cmath>

#include "groundstation/planning/catching_instant.hpp"

namespace {

using gs::model::PlanarFlightState;
namespace flight = gs::model::planar_flight;

gs::model::PlanarState<double> launch_state(double alpha, double alpha_dot, double vx, double vz) {
  gs::model::PlanarState<double> s = gs::model::PlanarState<double>::Zero();
  s(gs::model::planar::kX) = 1.5;
  s(gs::model::planar::kZ) = 2.0;
  s(gs::model::planar::kVx) = vx;
  s(gs::model::planar::kVz) = vz;
  s(gs::model::planar::kAlpha) = alpha;
  s(gs::model::planar::kAlphaDot) = alpha_dot;
  return s;
}

}  // namespace

TEST_CASE("the planar pole flight follows the 3D model with drag", "[planar_pole_flight]") {
  const gs::model::PoleParams params;
  // The Fig. 5 launch, a target throw's, a slow spin and one backwards.
  const auto [alpha, alpha_dot, vx, vz] = GENERATE(table<double, double, double, double>(
      {{0.48, 2.5, 0.3, 5.5}, {0.92, 2.8, 1.1, 2.2}, {0.2, 0.3, 2.0, 3.0}, {-0.5, -3.0, -1.0, 4.0}}));
  const gs::model::PlanarState<double> s = launch_state(alpha, alpha_dot, vx, vz);
  const PlanarFlightState<double> planar_launch = gs::model::planar_pole_at_launch<double>(s, params);
  const gs::model::PoleState pole = gs::planning::pole_state_at_launch(
      {s(gs::model::planar::kX), s(gs::model::planar::kZ), vx, vz, alpha, alpha_dot}, params);
  // The launch map agrees with catching_instant.hpp's (eq. (23), (26), (27)).
  CHECK(planar_launch(flight::kX) == Approx(pole.p_m.x()));
  CHECK(planar_launch(flight::kZ) == Approx(pole.p_m.z()));
  CHECK(planar_launch(flight::kVx) == Approx(pole.v_mps.x()));
  CHECK(planar_launch(flight::kVz) == Approx(pole.v_mps.z()));
  for (const double t : {0.4, 0.8, 1.2}) {
    const PlanarFlightState<double> planar =
        gs::model::planar_pole_flight<double>(planar_launch, t, 200, params);
    const gs::model::PoleState truth = gs::model::propagate_pole(pole, t, 1e-3, params);
    INFO("alpha " << alpha << ", t = " << t);
    CHECK(std::abs(planar(flight::kX) - truth.p_m.x()) < 1e-4);
    CHECK(std::abs(planar(flight::kZ) - truth.p_m.z()) < 1e-4);
    CHECK(std::abs(planar(flight::kVx) - truth.v_mps.x()) < 1e-4);
    CHECK(std::abs(planar(flight::kVz) - truth.v_mps.z()) < 1e-4);
    CHECK(std::abs(std::sin(planar(flight::kAlpha)) - truth.n.x()) < 1e-4);
    CHECK(std::abs(std::cos(planar(flight::kAlpha)) - truth.n.z()) < 1e-4);
    CHECK(std::abs(planar(flight::kAlphaDot) - truth.omega_radps.y()) < 1e-4);
  }
}

TEST_CASE("without drag the planar pole flies a parabola and spins at a constant rate",
          "[planar_pole_flight]") {
  const gs::model::PoleParams params = gs::model::without_drag(gs::model::PoleParams{});
  PlanarFlightState<double> s;
  s << 0.3, 2.0, 1.2, 4.0, 0.5, 2.5;
  const double t = 0.9;
  const PlanarFlightState<double> end = gs::model::planar_pole_flight<double>(s, t, 16, params);
  const double g = params.gravity_mps2;
  CHECK(end(flight::kX) == Approx(0.3 + 1.2 * t));
  CHECK(end(flight::kZ) == Approx(2.0 + 4.0 * t - 0.5 * g * t * t));
  CHECK(end(flight::kVz) == Approx(4.0 - g * t));
  CHECK(end(flight::kAlpha) == Approx(0.5 + 2.5 * t));
  CHECK(end(flight::kAlphaDot) == Approx(2.5));
}
