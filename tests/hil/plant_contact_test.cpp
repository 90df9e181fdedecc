// Contacts of the plant: a pole landing on a plate (and not staying up without control), a
// pole missing the plate, the momentum exchanged in an impact, what the IMU feels, friction,
// and the floor.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "hil/plant/plant.hpp"
#include "plant_test_configs.hpp"

using hil::Contact;
using hil::MotorCommands;
using hil::Plant;
using hil::PlantConfig;
using hil::Surface;
using hil::Vec3;

namespace {

PlantConfig quiet() { return plant_test::without_drag(plant_test::without_imu_errors()); }

const MotorCommands kOff{};

MotorCommands scaled(const MotorCommands& m, double factor) {
  MotorCommands out = m;
  for (double& c : out.command) c *= factor;
  return out;
}

// A pole standing on end 0 above vehicle 2's plate: its lower end `height_m` above the plate
// surface at `offset_m` from the plate centre, tilted by `tilt_rad` towards +x, at rest.
hil::PoleState pole_above_plate(const Plant& plant, const Vec3& offset_m, double height_m, double tilt_rad) {
  const double L = plant.config().pole.half_length_m;
  const Vec3 axis(std::sin(tilt_rad), 0.0, std::cos(tilt_rad));
  const Vec3 end = plant.plate_centre_m(pa::kVehicle2) + offset_m + Vec3(0, 0, height_m);
  return Plant::make_pole(end + L * axis, axis, Vec3::Zero(), Vec3::Zero());
}

}  // namespace

TEST_CASE("a pole dropped upright onto a hovering vehicle's plate stands for a moment, then falls") {
  Plant plant(quiet());
  plant.set_vehicle(pa::kVehicle2, plant.hovering_vehicle(Vec3(0, 0, 3.0), 0.0));
  plant.set_pole(pole_above_plate(plant, Vec3::Zero(), 0.02, 0.01));
  // The motors carry vehicle and pole; nothing balances the pole.
  const MotorCommands thrust = scaled(plant.hover_commands(pa::kVehicle2), 1.0 + 0.03 / 0.52);

  double landed_t = -1.0;
  double left_t = -1.0;
  for (int k = 0; k < 5000 && left_t < 0.0; ++k) {
    plant.step(0.001, kOff, thrust);
    for (const hil::PoleContactEvent& e : plant.take_contact_events()) {
      if (e.surface != Surface::plate2) continue;
      if (e.begins && landed_t < 0.0) {
        CHECK(e.end == 0);
        landed_t = e.t_s;
      }
      if (!e.begins) left_t = e.t_s;
    }
    if (std::abs(plant.t_s() - 0.4) < 1e-9) {
      // Standing: upright, on the plate, moving with the vehicle.
      CHECK(plant.pole_contact() == Contact::vehicle2);
      CHECK(plant.pole().axis().z() > 0.999);
      CHECK((plant.pole().body.velocity_mps - plant.vehicle(pa::kVehicle2).body.velocity_mps).norm() < 0.05);
    }
  }
  INFO("landed at " << landed_t << " s, left the plate at " << left_t << " s");
  CHECK(landed_t == Approx(std::sqrt(2.0 * 0.02 / 9.81)).margin(0.002));
  REQUIRE(left_t > 0.0);
  CHECK(left_t > 1.0);                   // the unstable fall takes a while to grow from 0.01 rad
  CHECK(plant.pole().axis().z() < 0.8);  // by then the pole has tipped well over
}

TEST_CASE("the plate is 0.12 m across: an end just inside its rim lands, one just outside falls past") {
  for (const double offset_m : {0.059, 0.061}) {
    Plant plant(quiet());
    plant.set_vehicle(pa::kVehicle2, plant.hovering_vehicle(Vec3(0, 0, 1.0), 0.0));
    plant.set_pole(pole_above_plate(plant, Vec3(0, offset_m, 0), 0.01, 0.01));
    bool touched_plate = false;
    double lowest_end_z = 10.0;
    for (int k = 0; k < 4000; ++k) {
      plant.step(0.001, kOff, plant.hover_commands(pa::kVehicle2));
      touched_plate = touched_plate || plant.pole_end_contact(0) == Contact::vehicle2;
      lowest_end_z = std::min(lowest_end_z, hil::pole_end_m(plant.pole(), plant.config().pole, 0).z());
    }
    INFO("offset " << offset_m);
    if (offset_m < 0.06) {
      CHECK(touched_plate);
    } else {
      CHECK_FALSE(touched_plate);
      CHECK(lowest_end_z < plant.plate_centre_m(pa::kVehicle2).z() - 0.5);  // it fell past the plate
      CHECK(plant.pole_contact() == Contact::floor);                        // and lies on the floor
      CHECK(std::abs(plant.pole().axis().z()) < 0.01);
    }
  }
}

TEST_CASE("an impact exchanges momentum: without gravity and thrust the total is conserved") {
  // The reference contact step, and the step scaled by the effective mass (plant.hpp), whose
  // longer steps leave RK4 a larger (still tiny) angular momentum error.
  const int by_mass = GENERATE(0, 1);
  const double angular_tolerance = by_mass ? 5e-8 : 1e-9;
  PlantConfig c = quiet();
  c.gravity_mps2 = 0.0;
  c.integration.contact_step_by_mass = by_mass;
  Plant plant(c);
  plant.set_vehicle(pa::kVehicle2,
                    plant.hovering_vehicle(Vec3(0, 0, 1.0), 0.0));  // floating, motors off below
  hil::VehicleState v = plant.vehicle(pa::kVehicle2);
  v.motor_thrust_N.fill(0.0);
  plant.set_vehicle(pa::kVehicle2, v);
  // An off-centre, oblique, spinning arrival.
  hil::PoleState pole = pole_above_plate(plant, Vec3(0.02, 0.01, 0), 0.005, 0.2);
  pole.body.velocity_mps = Vec3(0.5, 0.0, -3.0);
  pole.body.rate_body_radps = pole.body.attitude.conjugate() * Vec3(0.5, 1.0, 0.3);
  plant.set_pole(pole);

  const Vec3 origin(0.3, -0.2, 0.5);
  const Vec3 p0 = plant.pole_momentum_Ns() + plant.vehicle_momentum_Ns(pa::kVehicle2);
  const Vec3 l0 =
      plant.pole_angular_momentum_Nms(origin) + plant.vehicle_angular_momentum_Nms(pa::kVehicle2, origin);
  const double e0 = plant.pole_energy_J() + plant.vehicle_energy_J(pa::kVehicle2);
  bool touched = false;
  double worst_p = 0.0;
  double worst_l = 0.0;
  for (int k = 0; k < 100; ++k) {
    plant.step(0.001, kOff, kOff);
    touched = touched || plant.pole_end_contact(0) == Contact::vehicle2;
    const Vec3 p = plant.pole_momentum_Ns() + plant.vehicle_momentum_Ns(pa::kVehicle2);
    const Vec3 l =
        plant.pole_angular_momentum_Nms(origin) + plant.vehicle_angular_momentum_Nms(pa::kVehicle2, origin);
    worst_p = std::max(worst_p, (p - p0).norm());
    worst_l = std::max(worst_l, (l - l0).norm());
  }
  REQUIRE(touched);
  const double exchanged = plant.vehicle_momentum_Ns(pa::kVehicle2).norm();
  INFO("contact step by mass " << by_mass << ": exchanged " << exchanged << " N s; momentum error " << worst_p
                               << " N s, angular " << worst_l << " of " << l0.norm() << " N m s");
  CHECK(exchanged > 0.05);
  CHECK(worst_p < 1e-12);
  CHECK(worst_l < angular_tolerance * l0.norm() + 1e-12);
  // The off-centre hit turns the vehicle, and the impact loses energy (nearly inelastic).
  CHECK(plant.vehicle(pa::kVehicle2).body.rate_body_radps.norm() > 0.01);
  CHECK(plant.pole_energy_J() + plant.vehicle_energy_J(pa::kVehicle2) < e0 - 0.05);
}

TEST_CASE("in a plate impact under gravity and hover thrust, momentum changes only by the pole's weight") {
  Plant plant(quiet());
  plant.set_vehicle(pa::kVehicle2, plant.hovering_vehicle(Vec3(0, 0, 1.5), 0.0));
  plant.set_pole(pole_above_plate(plant, Vec3::Zero(), 0.3, 0.0));
  const MotorCommands hover = plant.hover_commands(pa::kVehicle2);
  // Until just before the impact: only the pole falls.
  while (hil::pole_end_m(plant.pole(), plant.config().pole, 0).z() >
         plant.plate_centre_m(pa::kVehicle2).z() + 0.005)
    plant.step(0.001, kOff, hover);
  const double t0 = plant.t_s();
  const Vec3 p0 = plant.pole_momentum_Ns() + plant.vehicle_momentum_Ns(pa::kVehicle2);
  const Vec3 pole0 = plant.pole_momentum_Ns();
  double peak_force = 0.0;
  for (int k = 0; k < 60; ++k) {
    plant.step(0.001, kOff, hover);
    peak_force = std::max(peak_force, plant.pole_end_force_N(0, Surface::plate2).norm());
  }
  const double dt = plant.t_s() - t0;
  const Vec3 p1 = plant.pole_momentum_Ns() + plant.vehicle_momentum_Ns(pa::kVehicle2);
  const Vec3 exchanged = plant.pole_momentum_Ns() - pole0;
  // The level vehicle's thrust balances its own weight exactly; the pole's weight is the only
  // external impulse.
  const Vec3 expected = Vec3(0, 0, -0.03 * 9.81 * dt);
  INFO("pole momentum change " << exchanged.transpose() << " N s, peak force " << peak_force << " N");
  CHECK(exchanged.z() > 0.06);  // the pole (2.4 m/s) was stopped
  CHECK((p1 - p0 - expected).norm() < 1e-9);
  CHECK(peak_force > 5.0);
  CHECK(peak_force < 0.52 * 50.0);  // below 50 m/s^2 on the vehicle (fw/config.hpp)
}

TEST_CASE("the IMU feels the impact as a drop of the body-z specific force") {
  Plant plant(quiet());
  plant.set_vehicle(pa::kVehicle2, plant.hovering_vehicle(Vec3(0, 0, 1.5), 0.0));
  plant.set_pole(pole_above_plate(plant, Vec3::Zero(), 0.3, 0.0));
  const MotorCommands hover = plant.hover_commands(pa::kVehicle2);
  double before = 0.0;
  double lowest = 1e9;
  double landed_t = -1.0;
  hil::ImuSample sample;
  for (int k = 0; k < 700; ++k) {
    plant.step(0.001, kOff, hover);
    for (const auto& e : plant.take_contact_events()) {
      if (e.begins && landed_t < 0.0) landed_t = e.t_s;
    }
    while (plant.pop_imu(pa::kVehicle2, sample)) {
      if (landed_t < 0.0) before = sample.accel_mps2.z();
      lowest = std::min(lowest, sample.accel_mps2.z());
    }
  }
  REQUIRE(landed_t > 0.0);
  const double after = plant.latest_imu(pa::kVehicle2).accel_mps2.z();
  INFO("specific force z: before " << before << ", lowest " << lowest << ", after " << after << " m/s^2");
  CHECK(before == Approx(9.81).epsilon(1e-9));
  CHECK(lowest < before - 10.0);
  CHECK(lowest > before - 50.0);
  // The pole then rests on the plate and both sink together under the same thrust: the IMU
  // reads g m_vehicle / (m_vehicle + m_pole).
  CHECK(after == Approx(9.81 * 0.52 / 0.55).epsilon(1e-4));
  // A central, vertical impact turns nothing.
  CHECK(plant.latest_imu(pa::kVehicle2).gyro_radps.norm() < 1e-9);
  CHECK(plant.latest_imu(pa::kVehicle2).accel_mps2.head<2>().norm() < 1e-9);
}

TEST_CASE("Coulomb friction: a pole sliding on the floor stops after v^2 / (2 mu g) and then stays") {
  const PlantConfig c = quiet();
  Plant plant(c);
  plant.set_pole(Plant::make_pole(Vec3(0, 0, 0), Vec3::UnitX(), Vec3(1.0, 0, 0), Vec3::Zero()));
  for (int k = 0; k < 500; ++k) plant.step(0.001, kOff, kOff);
  const double stop = 1.0 / (2.0 * c.contact.floor_friction * c.gravity_mps2);
  const double x_stopped = plant.pole().body.position_m.x();
  CHECK(x_stopped == Approx(stop).epsilon(0.02));
  CHECK(plant.pole_contact() == Contact::floor);
  for (int k = 0; k < 2000; ++k) plant.step(0.001, kOff, kOff);
  CHECK(std::abs(plant.pole().body.position_m.x() - x_stopped) < 1e-6);  // no creep
}

TEST_CASE("the floor stops a falling pole, which ends up lying on it") {
  Plant plant(quiet());
  plant.set_pole(Plant::make_pole(Vec3(0, 0, 2.0), Vec3(0.3, 0.1, 1.0), Vec3(0.2, 0, 0), Vec3(0.5, 2.0, 0)));
  double lowest = 10.0;
  for (int k = 0; k < 5000; ++k) {
    plant.step(0.001, kOff, kOff);
    lowest = std::min({lowest, hil::pole_end_m(plant.pole(), plant.config().pole, 0).z(),
                       hil::pole_end_m(plant.pole(), plant.config().pole, 1).z()});
  }
  CHECK(plant.pole_contact() == Contact::floor);
  CHECK(plant.pole_end_contact(0) == Contact::floor);
  CHECK(plant.pole_end_contact(1) == Contact::floor);
  CHECK(std::abs(plant.pole().body.position_m.z()) < 1e-3);
  CHECK(plant.pole().body.velocity_mps.norm() < 1e-4);
  CHECK(lowest > -0.02);
  // Lying still, it has been put to sleep; moving it wakes it.
  CHECK(plant.pole_asleep());
  plant.set_pole(Plant::make_pole(Vec3(0, 0, 1.0), Vec3::UnitX(), Vec3::Zero(), Vec3::Zero()));
  CHECK_FALSE(plant.pole_asleep());
  plant.step(0.1, kOff, kOff);
  CHECK(plant.pole().body.position_m.z() == Approx(1.0 - 0.5 * 9.81 * 0.01).epsilon(1e-9));
}

TEST_CASE("a pole taken down off a plate lies still on the floor where it was laid") {
  Plant plant(quiet());
  plant.set_vehicle(pa::kVehicle2, plant.hovering_vehicle(Vec3(0, 0, 2.0), 0.0));
  plant.place_pole_on(pa::kVehicle2);
  plant.step(0.01, kOff, plant.hover_commands(pa::kVehicle2));
  REQUIRE(plant.pole_contact() == Contact::vehicle2);
  plant.lay_pole_on_floor(Vec3(0.0, -2.0, 5.0));  // the height is the floor's, whatever is asked
  for (int k = 0; k < 500; ++k) plant.step(0.001, kOff, plant.hover_commands(pa::kVehicle2));
  CHECK(plant.pole_contact() == Contact::floor);
  CHECK(plant.pole_end_contact(0) == Contact::floor);
  CHECK(plant.pole_end_contact(1) == Contact::floor);
  CHECK(plant.pole().body.position_m.head<2>().isApprox(Eigen::Vector2d(0.0, -2.0), 1e-6));
  CHECK(std::abs(plant.pole().body.position_m.z()) < 1e-3);
  CHECK(plant.pole_asleep());
}

TEST_CASE("a new plant starts at rest: vehicles parked, the pole asleep on the floor") {
  Plant plant(quiet());
  CHECK(plant.vehicle_on_floor(pa::kVehicle1));
  CHECK(plant.vehicle_on_floor(pa::kVehicle2));
  CHECK(plant.pole_asleep());
  CHECK(plant.pole_end_contact(0) == Contact::floor);
  CHECK(plant.pole_end_contact(1) == Contact::floor);
  const Vec3 p0 = plant.pole().body.position_m;
  const Vec3 v0 = plant.vehicle(pa::kVehicle1).body.position_m;
  for (int k = 0; k < 1000; ++k) plant.step(0.001, kOff, kOff);
  CHECK((plant.pole().body.position_m - p0).norm() < 1e-12);
  CHECK((plant.vehicle(pa::kVehicle1).body.position_m - v0).norm() < 1e-9);
  CHECK(plant.take_contact_events().empty());
}

// integration_contact_step_by_mass (plant.hpp): an upright pole on a plate is integrated with
// steps about three times the reference's. What the firmware and the ground station see of a
// landing and of the stand and fall that follow (1.5 s, the fall amplifying every difference)
// must stay within half the motion capture's 1 mm / 1 mrad noise of the reference, within ten
// times the reference's own error (against half its step), and the impact's peak within 1 %.
TEST_CASE("the contact step scaled by the effective mass follows the reference step's landing and stand") {
  struct Run {
    std::vector<Vec3> pole_end_m, pole_axis, vehicle_m;
    double landed_t = -1.0, left_t = -1.0, lowest_mps2 = 1e9;
  };
  auto fly = [](int by_mass, double tilt_rad, const Vec3& offset_m, double contact_step_s = 0.0001) {
    PlantConfig c = quiet();
    c.integration.contact_step_by_mass = by_mass;
    c.integration.step_contact_s = contact_step_s;
    Plant plant(c);
    plant.set_vehicle(pa::kVehicle2, plant.hovering_vehicle(Vec3(0, 0, 3.0), 0.0));
    plant.set_pole(pole_above_plate(plant, offset_m, 0.2, tilt_rad));
    const MotorCommands thrust = scaled(plant.hover_commands(pa::kVehicle2), 1.0 + 0.03 / 0.52);
    Run run;
    hil::ImuSample sample;
    for (int k = 0; k < 1500; ++k) {
      plant.step(0.001, kOff, thrust);
      for (const hil::PoleContactEvent& e : plant.take_contact_events()) {
        if (e.surface != Surface::plate2) continue;
        if (e.begins && run.landed_t < 0.0) run.landed_t = e.t_s;
        if (!e.begins && run.left_t < 0.0) run.left_t = e.t_s;
      }
      while (plant.pop_imu(pa::kVehicle2, sample))
        run.lowest_mps2 = std::min(run.lowest_mps2, sample.accel_mps2.z());
      if (k % 10 == 9) {
        const double L = plant.config().pole.half_length_m;
        run.pole_end_m.push_back(plant.pole().body.position_m - L * plant.pole().axis());
        run.pole_axis.push_back(plant.pole().axis());
        run.vehicle_m.push_back(plant.vehicle(pa::kVehicle2).body.position_m);
      }
    }
    return run;
  };
  for (const double tilt_rad : {0.0, 0.02, 0.1}) {
    const Run reference = fly(0, tilt_rad, Vec3(0.01, -0.005, 0.0));
    const Run scaled_step = fly(1, tilt_rad, Vec3(0.01, -0.005, 0.0));
    const Run fine = fly(0, tilt_rad, Vec3(0.01, -0.005, 0.0), 0.00005);
    double end_m = 0.0, axis_rad = 0.0, vehicle_m = 0.0;
    double fine_end_m = 0.0, fine_axis_rad = 0.0, fine_vehicle_m = 0.0;
    for (std::size_t i = 0; i < reference.pole_end_m.size(); ++i) {
      fine_end_m = std::max(fine_end_m, (reference.pole_end_m[i] - fine.pole_end_m[i]).norm());
      fine_axis_rad = std::max(fine_axis_rad, (reference.pole_axis[i] - fine.pole_axis[i]).norm());
      fine_vehicle_m = std::max(fine_vehicle_m, (reference.vehicle_m[i] - fine.vehicle_m[i]).norm());
      end_m = std::max(end_m, (reference.pole_end_m[i] - scaled_step.pole_end_m[i]).norm());
      axis_rad = std::max(axis_rad, (reference.pole_axis[i] - scaled_step.pole_axis[i]).norm());
      vehicle_m = std::max(vehicle_m, (reference.vehicle_m[i] - scaled_step.vehicle_m[i]).norm());
    }
    INFO("tilt " << tilt_rad << " rad: pole end " << end_m << " m, axis " << axis_rad << " rad, vehicle "
                 << vehicle_m << " m apart; landed " << reference.landed_t << " / " << scaled_step.landed_t
                 << " s, lowest specific force " << reference.lowest_mps2 << " / " << scaled_step.lowest_mps2
                 << " m/s^2; the reference from half its step: " << fine_end_m << " m, " << fine_axis_rad
                 << " rad, " << fine_vehicle_m << " m; left " << reference.left_t << " / "
                 << scaled_step.left_t << " / " << fine.left_t << " s");
    REQUIRE(reference.landed_t > 0.0);
    CHECK(scaled_step.landed_t == Approx(reference.landed_t).margin(1e-4));
    CHECK(scaled_step.left_t == Approx(reference.left_t).margin(0.001));
    CHECK(scaled_step.lowest_mps2 == Approx(reference.lowest_mps2).epsilon(0.01));
    // Within half the motion capture's noise, and within ten times the reference's own error.
    CHECK(end_m < 5e-4);
    CHECK(axis_rad < 5e-4);
    CHECK(vehicle_m < 5e-4);
    CHECK(end_m < 10.0 * std::max(fine_end_m, 1e-5));
    CHECK(axis_rad < 10.0 * std::max(fine_axis_rad, 1e-5));
    CHECK(vehicle_m < 10.0 * std::max(fine_vehicle_m, 1e-5));
  }
}
