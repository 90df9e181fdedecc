// The throw's reach (groundstation/planning/throw_reach.hpp): the thrower's path and an upper
// bound on the pole's flight, checked against hand-worked numbers.
#include <catch2/catch.hpp>

#include <cmath>

#include "groundstation/planning/throw_reach.hpp"

namespace {

using gs::model::planar::kAlpha;
using gs::model::planar::kAlphaDot;
using gs::model::planar::kVx;
using gs::model::planar::kVz;
using gs::model::planar::kX;
using gs::model::planar::kZ;

gs::model::PlanarState<double> at(double x, double z) {
  gs::model::PlanarState<double> s = gs::model::PlanarState<double>::Zero();
  s(kX) = x;
  s(kZ) = z;
  return s;
}

}  // namespace

TEST_CASE("The reach holds the thrower's path and the pole's drag-free apex plus its half length") {
  gs::planning::ThrowTrajectory t;
  t.t_s = {0.0, 0.5, 1.0};
  t.state = {at(0.0, 0.0), at(-0.4, -0.3), at(1.5, 2.0)};
  // Launched upright (alpha 0) and not turning, rising at 4.905 m/s: the centre rises
  // v^2 / (2 g) = 1.226 m above its launch height z + L.
  t.state.back()(kVx) = 0.3;
  t.state.back()(kVz) = 4.905;
  gs::model::PoleParams pole;
  pole.half_length_m = 0.665;
  pole.gravity_mps2 = 9.81;
  const gs::planning::ThrowReach r = gs::planning::throw_reach(t, pole);
  const double centre_apex_z = 2.0 + 0.665 + 4.905 * 4.905 / (2.0 * 9.81);
  CHECK(r.pole_apex_m == Approx(centre_apex_z + 0.665));
  CHECK(r.max_m.z() == Approx(centre_apex_z + 0.665));
  CHECK(r.min_m.z() == Approx(-0.3));  // the path's dip
  CHECK(r.min_m.x() == Approx(-0.4));
  // The apex lies 0.5 s on at 0.3 m/s along the throw, the pole's end up to L beyond it.
  CHECK(r.max_m.x() == Approx(1.5 + 0.3 * 0.5 + 0.665));
  CHECK(r.min_m.y() == Approx(-0.665));
  CHECK(r.max_m.y() == Approx(0.665));
}

TEST_CASE("A tilted, turning pole's apex follows its centre's velocity (eqs. 23, 26)") {
  gs::planning::ThrowTrajectory t;
  t.t_s = {0.0};
  t.state = {at(0.0, 0.0)};
  t.state.back()(kAlpha) = 0.5;
  t.state.back()(kAlphaDot) = 2.0;
  t.state.back()(kVz) = 5.0;
  gs::model::PoleParams pole;
  const gs::planning::ThrowReach r = gs::planning::throw_reach(t, pole);
  // Centre at L (sin a, cos a), its vertical speed vz - L a' sin a.
  const double L = pole.half_length_m;
  const double vz = 5.0 - L * 2.0 * std::sin(0.5);
  const double apex = L * std::cos(0.5) + vz * vz / (2.0 * pole.gravity_mps2) + L;
  CHECK(r.pole_apex_m == Approx(apex));
}

TEST_CASE("A falling launch reaches no higher than its start and an empty plan reaches nothing") {
  gs::planning::ThrowTrajectory t;
  t.t_s = {0.0};
  t.state = {at(0.0, 1.0)};
  t.state.back()(kVz) = -1.0;
  gs::model::PoleParams pole;
  CHECK(gs::planning::throw_reach(t, pole).pole_apex_m == Approx(1.0 + 2.0 * pole.half_length_m));
  const gs::planning::ThrowReach none = gs::planning::throw_reach(gs::planning::ThrowTrajectory{}, pole);
  CHECK(none.pole_apex_m == 0.0);
  CHECK(none.max_m.isZero());
}
