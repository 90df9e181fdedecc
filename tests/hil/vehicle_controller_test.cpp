// The scenario runner's controllers (hil/plant/vehicle_controller.hpp): the body-rate loop that
// flies the ground station's inputs (collective thrust, body rates) on the plant.
#include <catch2/catch.hpp>
#include <cmath>

#include "hil/plant/plant.hpp"
#include "hil/plant/vehicle_controller.hpp"
#include "plant_test_configs.hpp"

using hil::Plant;
using hil::Vec3;

namespace {

// Flies vehicle 1 from hover for `duration_s` on constant inputs; the rate loop at 1 kHz.
Plant fly_rates(double thrust_mps2, const Vec3& rates_radps, double duration_s) {
  const hil::PlantConfig config = plant_test::without_drag(plant_test::without_imu_errors());
  Plant plant(config, 1);
  plant.set_vehicle(pa::kVehicle1, plant.hovering_vehicle(Vec3(0.0, 0.0, 20.0), 0.0));
  const hil::VehicleController loop(config.vehicle, config.gravity_mps2);
  for (int k = 0; k < static_cast<int>(std::lround(duration_s / 1e-3)); ++k) {
    plant.step(1e-3, loop.track_rates(plant.vehicle(pa::kVehicle1), thrust_mps2, rates_radps),
               hil::MotorCommands{});
  }
  return plant;
}

}  // namespace

TEST_CASE("the rate loop holds a commanded pitch rate and keeps the other axes still") {
  const Plant plant = fly_rates(9.81, Vec3(0.0, 1.5, 0.0), 0.3);
  const Vec3 w = plant.vehicle(pa::kVehicle1).body.rate_body_radps;
  CHECK(w.y() == Approx(1.5).margin(0.05));
  CHECK(std::abs(w.x()) < 0.01);
  CHECK(std::abs(w.z()) < 0.01);
}

TEST_CASE("the rate loop's collective thrust gives the commanded acceleration along body z") {
  // Level, no rates: a_q = 12 m/s^2 climbs at 12 - g once the motors have caught up.
  const Plant plant = fly_rates(12.0, Vec3::Zero(), 0.5);
  double thrust_N = 0.0;
  for (double f : plant.vehicle(pa::kVehicle1).motor_thrust_N) thrust_N += f;
  CHECK(thrust_N / plant.config().vehicle.mass_kg == Approx(12.0).epsilon(0.01));
  CHECK(plant.vehicle(pa::kVehicle1).body.velocity_mps.z() > 0.5 * (12.0 - 9.81) * 0.5);
}
