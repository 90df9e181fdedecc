// The pole's centre of mass off its middle: where its ends lie, what the motion capture sees,
// its inertia, the drag's torque, a pole handed up, and the envelope's draw.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "hil/plant/plant.hpp"
#include "hil/plant/pole_drag.hpp"
#include "hil/plant/randomisation.hpp"

using hil::Plant;
using hil::PlantConfig;
using hil::Vec3;

namespace {

constexpr double kOffset_m = 0.01;

PlantConfig offset_config(double offset_m) {
  PlantConfig c;
  c.pole.centre_of_mass_offset_m = offset_m;
  c.mocap.position_noise_m = 0.0;
  c.mocap.attitude_noise_rad = 0.0;
  return c;
}

}  // namespace

TEST_CASE("the ends lie L + d and L - d from a centre of mass d towards end 1") {
  const PlantConfig c = offset_config(kOffset_m);
  const hil::PoleState pole =
      Plant::make_pole(Vec3(1.0, 2.0, 3.0), Vec3::UnitZ(), Vec3::Zero(), Vec3::Zero());
  CHECK(hil::pole_end_m(pole, c.pole, 0).z() == Approx(3.0 - c.pole.half_length_m - kOffset_m));
  CHECK(hil::pole_end_m(pole, c.pole, 1).z() == Approx(3.0 + c.pole.half_length_m - kOffset_m));
  CHECK(c.pole.longest_lever_m() == Approx(c.pole.half_length_m + kOffset_m));
}

TEST_CASE("a pole handed up rests with end 0 on the plate and the motion capture sees its middle") {
  for (const double d : {kOffset_m, -kOffset_m}) {
    Plant plant(offset_config(d));
    plant.place_pole_on(pa::kVehicle1);
    const Vec3 plate = plant.plate_centre_m(pa::kVehicle1);
    const double L = plant.config().pole.half_length_m;
    CHECK((hil::pole_end_m(plant.pole(), plant.config().pole, 0) - plate).norm() < 1e-12);
    CHECK(plant.pole().body.position_m.z() == Approx(plate.z() + L + d));
    // The first frame is captured at t = 0; run past the motion capture's latency.
    hil::CapturedFrame frame;
    bool seen = false;
    for (int k = 0; k < 100 && !seen; ++k) {
      plant.step(0.001, {}, {});
      seen = plant.pop_mocap(frame);
    }
    REQUIRE(seen);
    const hil::CapturedPose& pole = frame.pose[static_cast<std::size_t>(hil::Body::pole)];
    REQUIRE(pole.seen);
    // Captured at t = 0, before the pole moved: the middle, L above the plate.
    CHECK(pole.position_m.z() == Approx(plate.z() + L).margin(1e-9));
  }
}

TEST_CASE("the transverse inertia about the centre of mass is the middle's less m d^2") {
  const Plant middle(offset_config(0.0));
  const Plant off(offset_config(kOffset_m));
  const double m = off.config().pole.mass_kg;
  CHECK(middle.pole_transverse_inertia_kgm2() - off.pole_transverse_inertia_kgm2() ==
        Approx(m * kOffset_m * kOffset_m).epsilon(1e-9));
}

TEST_CASE("drag across a pole whose centre of mass is off its middle turns it towards the flow") {
  // Moving along x across a pole along z, the drag acts at the middle, d below the centre of
  // mass: about the centre of mass its torque is (-d n) x F, zero without offset, with (15)'s
  // coefficient c_rot in place of the force's c_xy.
  const hil::PoleConfig pole = offset_config(kOffset_m).pole;
  const Vec3 velocity(2.0, 0.0, 0.0);
  const Vec3 axis = Vec3::UnitZ();
  const hil::Wrench symmetric = hil::pole_drag(offset_config(0.0).pole, velocity, Vec3::Zero(), axis);
  const hil::Wrench off = hil::pole_drag(pole, velocity, Vec3::Zero(), axis);
  CHECK(symmetric.torque_Nm.norm() < 1e-15);
  CHECK((off.force_N - symmetric.force_N).norm() < 1e-12 * symmetric.force_N.norm());
  const Vec3 expected =
      pole.drag_rotational_kgpm2 / pole.drag_normal_kgpm2 * (-kOffset_m * axis).cross(off.force_N);
  CHECK(expected.norm() > 0.0);
  CHECK((off.torque_Nm - expected).norm() < 1e-9 * expected.norm());
}

TEST_CASE("the envelope draws the centre of mass within its range, recorded with the draws") {
  PlantConfig nominal;
  nominal.randomisation.profile = 1;
  double lowest = 1.0, highest = -1.0;
  for (std::uint64_t seed = 1; seed <= 200; ++seed) {
    const PlantConfig c = hil::randomised(nominal, seed);
    const double d = c.pole.centre_of_mass_offset_m;
    lowest = std::min(lowest, d);
    highest = std::max(highest, d);
    bool recorded = false;
    for (const hil::DrawnParameter& p : hil::drawn_parameters(c))
      recorded = recorded || (p.key == "pole_centre_of_mass_offset_m" && p.value == d);
    CHECK(recorded);
  }
  const double max_m = nominal.envelope.pole_centre_of_mass_max_m;
  CHECK(lowest >= -max_m);
  CHECK(highest <= max_m);
  // 200 draws from U(-1 cm, 1 cm) reach beyond +-8 mm on both sides.
  CHECK(lowest < -0.8 * max_m);
  CHECK(highest > 0.8 * max_m);
}
