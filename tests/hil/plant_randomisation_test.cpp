// Per-run randomisation of the uncertain plant parameters: reproducible for a seed, different
// between seeds, within the configured spreads; and whole runs reproducible for a seed.
#include <catch2/catch.hpp>

#include "hil/plant/plant.hpp"
#include "hil/plant/randomisation.hpp"

using hil::PlantConfig;
using hil::Vec3;

namespace {

bool within(double value, double nominal, double fraction) {
  return value >= nominal * (1.0 - fraction) && value <= nominal * (1.0 + fraction);
}

// A short run with sensors on: the IMU samples and motion-capture frames it produced.
struct Trace {
  std::vector<double> numbers;
};

Trace run(const PlantConfig& c, std::uint64_t seed) {
  hil::Plant plant(c, seed);
  plant.set_vehicle(pa::kVehicle1, plant.hovering_vehicle(Vec3(0, 0, 1.0), 0.0));
  plant.set_pole(hil::Plant::make_pole(Vec3(1, 0, 2), Vec3(0.3, 0, 1), Vec3(0, 0, 3), Vec3(0, 2, 0)));
  Trace t;
  for (int k = 0; k < 200; ++k) {
    plant.step(0.001, plant.hover_commands(pa::kVehicle1), hil::MotorCommands{});
    hil::ImuSample s;
    while (plant.pop_imu(pa::kVehicle1, s)) {
      for (int i = 0; i < 3; ++i) t.numbers.push_back(s.accel_mps2[i]);
    }
    hil::CapturedFrame f;
    while (plant.pop_mocap(f)) {
      for (const auto& p : f.pose) {
        for (int i = 0; i < 3; ++i) t.numbers.push_back(p.position_m[i]);
      }
    }
  }
  for (int i = 0; i < 3; ++i) t.numbers.push_back(plant.pole().body.position_m[i]);
  return t;
}

}  // namespace

TEST_CASE("randomisation is reproducible for a seed and differs between seeds") {
  const PlantConfig nominal;
  const PlantConfig a = hil::randomised(nominal, 11);
  const PlantConfig b = hil::randomised(nominal, 11);
  const PlantConfig c = hil::randomised(nominal, 12);
  CHECK(hil::format_plant_config(a) == hil::format_plant_config(b));
  CHECK(hil::format_plant_config(a) != hil::format_plant_config(c));
  CHECK(a.pole.drag_normal_kgpm2 != c.pole.drag_normal_kgpm2);
  CHECK(a.mocap.latency_s != c.mocap.latency_s);
  CHECK(a.vehicle.motor_gain[0][0] != c.vehicle.motor_gain[0][0]);
  // Not touched: what is not uncertain.
  CHECK(a.pole.radius_m == nominal.pole.radius_m);
  CHECK(a.vehicle.plate_radius_m == nominal.vehicle.plate_radius_m);
  CHECK(a.mocap.rate_Hz == nominal.mocap.rate_Hz);
}

TEST_CASE("randomised parameters stay within their spreads and cover them") {
  const PlantConfig n;
  const hil::RandomisationConfig& r = n.randomisation;
  double drag_lo = 1e9, drag_hi = 0.0, latency_lo = 1e9, latency_hi = 0.0, gain_lo = 1e9, gain_hi = 0.0;
  double mass_lo = 1e9, mass_hi = 0.0, length_lo = 1e9, length_hi = 0.0, loss_lo = 1e9, loss_hi = 0.0;
  for (std::uint64_t seed = 0; seed < 400; ++seed) {
    const PlantConfig c = hil::randomised(n, seed);
    INFO("seed " << seed);
    CHECK(within(c.pole.drag_axial_kgpm2, n.pole.drag_axial_kgpm2, r.drag_fraction));
    CHECK(within(c.pole.drag_normal_kgpm2, n.pole.drag_normal_kgpm2, r.drag_fraction));
    CHECK(within(c.pole.drag_rotational_kgpm2, n.pole.drag_rotational_kgpm2, r.drag_fraction));
    for (const auto& vehicle : c.vehicle.motor_gain) {
      for (const double g : vehicle) {
        CHECK(within(g, 1.0, r.motor_gain_fraction));
        gain_lo = std::min(gain_lo, g);
        gain_hi = std::max(gain_hi, g);
      }
    }
    CHECK(within(c.vehicle.motor_time_constant_s, n.vehicle.motor_time_constant_s,
                 r.motor_time_constant_fraction));
    CHECK(within(c.contact.plate_friction, n.contact.plate_friction, r.friction_fraction));
    CHECK(within(c.imu.accel_noise_mps2, n.imu.accel_noise_mps2, r.noise_fraction));
    CHECK(within(c.mocap.position_noise_m, n.mocap.position_noise_m, r.noise_fraction));
    CHECK(c.mocap.latency_s >= r.latency_min_s);
    CHECK(c.mocap.latency_s <= r.latency_max_s);
    CHECK(within(c.pole.mass_kg, n.pole.mass_kg, r.pole_mass_fraction));
    CHECK(within(c.pole.half_length_m, n.pole.half_length_m, r.pole_length_fraction));
    CHECK(c.radio_loss_probability >= r.radio_loss_min);
    CHECK(c.radio_loss_probability <= r.radio_loss_max);
    mass_lo = std::min(mass_lo, c.pole.mass_kg / n.pole.mass_kg);
    mass_hi = std::max(mass_hi, c.pole.mass_kg / n.pole.mass_kg);
    length_lo = std::min(length_lo, c.pole.half_length_m / n.pole.half_length_m);
    length_hi = std::max(length_hi, c.pole.half_length_m / n.pole.half_length_m);
    loss_lo = std::min(loss_lo, c.radio_loss_probability);
    loss_hi = std::max(loss_hi, c.radio_loss_probability);
    CHECK(hil::check_plant_config(c).empty());
    drag_lo = std::min(drag_lo, c.pole.drag_normal_kgpm2);
    drag_hi = std::max(drag_hi, c.pole.drag_normal_kgpm2);
    latency_lo = std::min(latency_lo, c.mocap.latency_s);
    latency_hi = std::max(latency_hi, c.mocap.latency_s);
  }
  // The draws use the whole range.
  CHECK(drag_lo < n.pole.drag_normal_kgpm2 * 0.75);
  CHECK(drag_hi > n.pole.drag_normal_kgpm2 * 1.25);
  CHECK(latency_lo < 0.007);
  CHECK(latency_hi > 0.018);
  CHECK(gain_lo < 0.955);
  CHECK(gain_hi > 1.045);
  CHECK(mass_lo < 0.975);
  CHECK(mass_hi > 1.025);
  CHECK(length_lo < 0.985);
  CHECK(length_hi > 1.015);
  CHECK(loss_lo < 0.002);
  CHECK(loss_hi > 0.018);
}

TEST_CASE("a run is reproducible for a seed, and its sensor noise differs between seeds") {
  const PlantConfig c;
  const Trace a = run(c, 5);
  const Trace b = run(c, 5);
  const Trace other = run(c, 6);
  REQUIRE(a.numbers.size() > 600);
  CHECK(a.numbers == b.numbers);
  CHECK(a.numbers != other.numbers);
  // The true pole does not depend on the sensor seed.
  CHECK(a.numbers.back() == other.numbers.back());
}
