// The pole in free flight: conservation laws without drag, the ballistic path, the drag law's
// quadrature against closed forms, and energy that only falls with drag.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "hil/plant/plant.hpp"
#include "hil/plant/pole_drag.hpp"

using hil::Plant;
using hil::PlantConfig;
using hil::Vec3;

namespace {

PlantConfig quiet_config(bool drag) {
  PlantConfig c;
  if (!drag) {
    c.pole.drag_axial_kgpm2 = 0.0;
    c.pole.drag_normal_kgpm2 = 0.0;
    c.pole.drag_rotational_kgpm2 = 0.0;
  }
  return c;
}

const hil::MotorCommands kOff{};

}  // namespace

TEST_CASE("a free pole without drag keeps its energy and angular momentum and flies a parabola") {
  Plant plant(quiet_config(false));
  const Vec3 p0(0.3, -0.2, 50.0);
  const Vec3 v0(1.0, -0.5, 3.0);
  // A tumbling pole with some spin about its own axis.
  const Vec3 axis = Vec3(0.3, 0.2, 0.93).normalized();
  const Vec3 rate(2.0, -3.0, 1.5);
  plant.set_pole(Plant::make_pole(p0, axis, v0, rate));

  const double e0 = plant.pole_energy_J();
  const double kinetic0 = e0 - 0.03 * 9.81 * p0.z();  // drift is measured against this
  const Vec3 l0 = plant.pole_angular_momentum_Nms(p0);
  const double spin0 = plant.pole().body.rate_inertial_radps().dot(plant.pole().axis());
  double worst_energy = 0.0;
  double worst_momentum = 0.0;
  double worst_path = 0.0;
  double worst_spin = 0.0;
  for (int k = 1; k <= 2000; ++k) {
    plant.step(0.001, kOff, kOff);
    const double t = plant.t_s();
    const Vec3 expected = p0 + v0 * t + 0.5 * t * t * Vec3(0.0, 0.0, -9.81);
    const Vec3 centre = plant.pole().body.position_m;
    worst_energy = std::max(worst_energy, std::abs(plant.pole_energy_J() - e0) / kinetic0);
    // About the moving centre, the angular momentum is the body's own spin: conserved.
    worst_momentum =
        std::max(worst_momentum, (plant.pole_angular_momentum_Nms(centre) - l0).norm() / l0.norm());
    worst_path = std::max(worst_path, (centre - expected).norm());
    worst_spin = std::max(worst_spin,
                          std::abs(plant.pole().body.rate_inertial_radps().dot(plant.pole().axis()) - spin0));
  }
  INFO("energy drift " << worst_energy << " of the kinetic energy, angular momentum drift " << worst_momentum
                       << ", path error " << worst_path << " m");
  CHECK(worst_energy < 1e-9);
  CHECK(worst_momentum < 1e-9);
  CHECK(worst_path < 1e-9);
  CHECK(worst_spin < 1e-9);
  CHECK(plant.pole_contact() == hil::Contact::none);
}

TEST_CASE("the drag quadrature converges to the closed forms of eqs. (10)-(15)") {
  hil::PoleConfig pole;
  pole.drag_segments = 2000;
  const double L = pole.half_length_m;
  const Vec3 n = Vec3::UnitZ();
  SECTION("moving along its axis: only c_z acts, on the whole length") {
    const hil::Wrench w = hil::pole_drag(pole, Vec3(0, 0, 4.0), Vec3::Zero(), n);
    CHECK(w.force_N.z() == Approx(-pole.drag_axial_kgpm2 * 16.0 * 2.0 * L).epsilon(1e-12));
    CHECK(w.force_N.head<2>().norm() < 1e-15);
    CHECK(w.torque_Nm.norm() < 1e-15);
  }
  SECTION("moving broadside: only c_xy acts") {
    const hil::Wrench w = hil::pole_drag(pole, Vec3(3.0, 0, 0), Vec3::Zero(), n);
    CHECK(w.force_N.x() == Approx(-pole.drag_normal_kgpm2 * 9.0 * 2.0 * L).epsilon(1e-12));
    CHECK(std::abs(w.force_N.z()) < 1e-15);
  }
  SECTION("turning about a transverse axis: no net force, torque c_rot w^2 L^4 / 2 against the turn") {
    const double w_radps = 5.0;
    const hil::Wrench w = hil::pole_drag(pole, Vec3::Zero(), Vec3(0, w_radps, 0), n);
    CHECK(w.force_N.norm() < 1e-12);
    CHECK(w.torque_Nm.y() ==
          Approx(-pole.drag_rotational_kgpm2 * w_radps * w_radps * std::pow(L, 4) / 2.0).epsilon(1e-5));
  }
  SECTION("with the default 20 segments the turning torque is within 0.5 % (plant.yaml)") {
    hil::PoleConfig coarse;
    const double w_radps = 5.0;
    const double exact = -coarse.drag_rotational_kgpm2 * w_radps * w_radps * std::pow(L, 4) / 2.0;
    const hil::Wrench w = hil::pole_drag(coarse, Vec3::Zero(), Vec3(0, w_radps, 0), n);
    CHECK(std::abs(w.torque_Nm.y() / exact - 1.0) <= 0.005);
  }
  SECTION("spinning about its own axis: nothing") {
    const hil::Wrench w = hil::pole_drag(pole, Vec3::Zero(), Vec3(0, 0, 30.0), n);
    CHECK(w.force_N.norm() < 1e-15);
    CHECK(w.torque_Nm.norm() < 1e-15);
  }
}

namespace {

// The paper's law point by point, eqs. (12)-(15), by the same midpoint rule: what pole_drag()
// evaluates on scalars (the axial part is constant along the pole) must give the same wrench.
hil::Wrench drag_point_by_point(const hil::PoleConfig& pole, const Vec3& v_p, const Vec3& omega,
                                const Vec3& n) {
  hil::Wrench w;
  const double dxi = 2.0 * pole.half_length_m / pole.drag_segments;
  for (int j = 0; j < pole.drag_segments; ++j) {
    const double xi = -pole.half_length_m + (j + 0.5) * dxi;
    const Vec3 v = v_p + xi * omega.cross(n);
    const Vec3 v_axial = v.dot(n) * n;
    const Vec3 v_across = v - v_axial;
    w.force_N -= (pole.drag_axial_kgpm2 * v_axial.norm() * v_axial +
                  pole.drag_normal_kgpm2 * v_across.norm() * v_across) *
                 dxi;
    w.torque_Nm -= pole.drag_rotational_kgpm2 * (xi * n).cross(v.norm() * v) * dxi;
  }
  return w;
}

}  // namespace

TEST_CASE("the drag on scalars equals the point-by-point midpoint rule within 1e-12 of its scale") {
  hil::PoleConfig pole;
  std::uint64_t state = 12345;
  auto uniform = [&state](double lo, double hi) {  // a fixed LCG: the cases do not depend on the library
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return lo + (hi - lo) * static_cast<double>(state >> 11) / 9007199254740992.0;
  };
  auto vec = [&uniform](double r) { return Vec3(uniform(-r, r), uniform(-r, r), uniform(-r, r)); };
  double worst = 0.0;
  for (int i = 0; i < 2000; ++i) {
    pole.drag_segments = i % 3 == 0 ? 20 : 1 + i % 50;
    const Vec3 n = vec(1.0).normalized();
    // Throws, balancing, and the hard cases: pure rotation (the across velocity passes through
    // zero on the pole), pure axial motion, rest.
    Vec3 v = vec(i % 5 == 0 ? 0.0 : 8.0), omega = vec(i % 7 == 0 ? 0.0 : 20.0);
    if (i % 11 == 0) v = v.dot(n) * n;
    const hil::Wrench fast = hil::pole_drag(pole, v, omega, n);
    const hil::Wrench ref = drag_point_by_point(pole, v, omega, n);
    // Relative to the wrench's scale, c (|v| + L |omega|)^2 2L (and times L for the torque): a
    // component that cancels to zero by symmetry is compared with the size of its terms.
    const double speed = v.norm() + pole.half_length_m * omega.norm();
    const double scale_f = pole.drag_normal_kgpm2 * speed * speed * 2.0 * pole.half_length_m;
    const double scale_t =
        pole.drag_rotational_kgpm2 * speed * speed * 2.0 * pole.half_length_m * pole.half_length_m;
    if (speed == 0.0) {
      CHECK(fast.force_N.norm() == 0.0);
      CHECK(fast.torque_Nm.norm() == 0.0);
      continue;
    }
    worst = std::max({worst, (fast.force_N - ref.force_N).norm() / scale_f,
                      (fast.torque_Nm - ref.torque_Nm).norm() / scale_t});
  }
  INFO("worst difference " << worst << " of the wrench's scale");
  CHECK(worst < 1e-12);
}

TEST_CASE("with drag the free pole's energy falls at every step, and the flight is shorter") {
  PlantConfig config = quiet_config(true);
  Plant with_drag(config);
  Plant without_drag(quiet_config(false));
  // The paper's Fig. 5 launch: centre velocity (0.3, 0, 5.5) m/s, alpha 0.48 rad, alpha' 2.5 rad/s.
  const Vec3 axis(std::sin(0.48), 0.0, std::cos(0.48));
  const hil::PoleState launch = Plant::make_pole(Vec3(1.5, 0, 2.6), axis, Vec3(0.3, 0, 5.5), Vec3(0, 2.5, 0));
  with_drag.set_pole(launch);
  without_drag.set_pole(launch);
  double previous = with_drag.pole_energy_J();
  const double e0 = previous;
  int rises = 0;
  for (int k = 0; k < 1000; ++k) {
    with_drag.step(0.001, kOff, kOff);
    without_drag.step(0.001, kOff, kOff);
    const double e = with_drag.pole_energy_J();
    if (e > previous) ++rises;
    previous = e;
  }
  CHECK(rises == 0);
  INFO("energy lost to drag in 1 s: " << e0 - previous << " J");
  CHECK(e0 - previous > 0.01);
  CHECK(with_drag.pole().body.position_m.z() < without_drag.pole().body.position_m.z() - 0.01);
}
