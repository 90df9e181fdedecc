// The attempt's admission (groundstation/runtime/attempt_admission.hpp): each refusal on its own,
// in the order the runtime checks them, with the numbers its reason gives.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>

#include "groundstation/runtime/attempt_admission.hpp"

namespace {

using gs::runtime::admit_request;
using gs::runtime::admit_vehicles;
using gs::runtime::AttemptRefusal;
using gs::runtime::peak_thrust_mps2;
using gs::runtime::refusal_name;
using gs::runtime::stronger_thrower;
using gs::runtime::thrust_ceiling_mps2;
using gs::runtime::thrust_shortfall;
using gs::runtime::ThrustAdmission;
using gs::runtime::VehicleThrust;

// A throw whose thrust peaks at `peak_mps2` in the middle of three points.
gs::planning::ThrowTrajectory throw_peaking_at(double peak_mps2) {
  gs::planning::ThrowTrajectory t;
  t.t_s = {0.0, 0.5, 1.0};
  for (double a : {9.81, peak_mps2, 5.0}) {
    gs::model::PlanarInput<double> u = gs::model::PlanarInput<double>::Zero();
    u(gs::model::planar::kThrust) = a;
    t.input.push_back(u);
  }
  return t;
}

// The defaults: a_q,max 20 m/s^2, 0.9 of the peak needed, V_ref 12.6 V, the catch's peak g + 4.19.
// A 20 m/s^2 airframe, for round numbers.
const ThrustAdmission kSettings{20.0};

}  // namespace

TEST_CASE("The request's own refusals: one attempt at a time, a thrower of the act") {
  CHECK(admit_request(false, pa::kVehicle1).admitted());
  CHECK(admit_request(false, pa::kVehicle2).admitted());
  const auto busy = admit_request(true, pa::kVehicle1);
  CHECK(busy.refusal == AttemptRefusal::busy);
  CHECK(busy.why == "an attempt is running");
  const auto stranger = admit_request(false, pa::VehicleId(7));
  CHECK(stranger.refusal == AttemptRefusal::not_of_act);
  CHECK(stranger.why == "vehicle 7 is not of the act");
  CHECK(admit_request(true, pa::VehicleId(7)).refusal == AttemptRefusal::busy);  // busy first
}

TEST_CASE("Every refusal has a name for the logs") {
  CHECK(refusal_name(AttemptRefusal::none) == "none");
  CHECK(refusal_name(AttemptRefusal::busy) == "ground_station_busy");
  CHECK(refusal_name(AttemptRefusal::not_of_act) == "not_of_act");
  CHECK(refusal_name(AttemptRefusal::target_not_planned) == "target_throw_not_planned");
  CHECK(refusal_name(AttemptRefusal::too_weak) == "vehicle_too_weak");
  CHECK(refusal_name(AttemptRefusal::outside_volume) == "outside_arena_volume");
}

TEST_CASE("The arena's volume: the throw's reach, turned into the arena, and the catch point inside it") {
  gs::runtime::ArenaVolume volume;
  volume.min_m = Eigen::Vector3d(-2.0, -3.0, 0.0);
  volume.max_m = Eigen::Vector3d(6.0, 3.0, 8.0);
  volume.margin_m = 0.3;
  gs::planning::ThrowReach reach;
  reach.min_m = Eigen::Vector3d(-0.2, -0.7, -0.1);
  reach.max_m = Eigen::Vector3d(2.5, 0.7, 5.5);
  reach.pole_apex_m = 5.5;
  gs::control::ThrowFrame frame;
  frame.origin_m = Eigen::Vector3d(0.0, 0.0, 1.0);
  const Eigen::Vector3d catch_point(4.0, 0.0, 3.0);
  CHECK(gs::runtime::admit_volume(reach, frame, catch_point, volume).admitted());

  // Under a 6.6 m ceiling the pole's end (5.5 m above the 1 m origin) is 0.2 m into the margin.
  volume.max_m.z() = 6.6;
  const auto low = gs::runtime::admit_volume(reach, frame, catch_point, volume);
  CHECK(low.refusal == AttemptRefusal::outside_volume);
  CHECK(low.why ==
        "the throw reaches z = 6.50 m, 0.20 m beyond the arena's upper bound 6.60 m (margin 0.30 m)");
  volume.max_m.z() = 8.0;

  // Thrown the other way (yaw pi), the frame's x runs towards -x: 2.5 m of it passes -2 + 0.3.
  frame.yaw_rad = M_PI;
  const auto back = gs::runtime::admit_volume(reach, frame, catch_point, volume);
  CHECK(back.refusal == AttemptRefusal::outside_volume);
  CHECK(back.why ==
        "the throw reaches x = -2.50 m, 0.80 m beyond the arena's lower bound -2.00 m (margin 0.30 m)");
  frame.yaw_rad = 0.0;

  // A catch point by the wall.
  const auto wall = gs::runtime::admit_volume(reach, frame, Eigen::Vector3d(4.0, 2.9, 3.0), volume);
  CHECK(wall.refusal == AttemptRefusal::outside_volume);
  CHECK(wall.why ==
        "the catch reaches y = 2.90 m, 0.20 m beyond the arena's upper bound 3.00 m (margin 0.30 m)");
}

TEST_CASE("A throw to a target that could not be planned is refused before any thrust is checked") {
  const VehicleThrust weak{pa::kVehicle1, 0.1, 0.0};
  const auto a = admit_vehicles(nullptr, weak, weak, kSettings);
  CHECK(a.refusal == AttemptRefusal::target_not_planned);
  CHECK(a.why == "the throw to the target cannot be planned");
}

TEST_CASE("The throw's peak is the trajectory's highest thrust and the pole's push the thrower carries") {
  CHECK(peak_thrust_mps2(throw_peaking_at(17.1), 0.0) == 17.1);
  CHECK(peak_thrust_mps2(gs::planning::ThrowTrajectory{}, 0.05) == 0.0);
  // The pole upright and still on the plate presses with all of a_q: m_p / m_q of it added.
  CHECK(peak_thrust_mps2(throw_peaking_at(17.1), 0.05) == Approx(17.1 * 1.05));
}

TEST_CASE("The thrower is refused below min_thrust_fraction of the throw's peak, exactly at the edge") {
  const gs::planning::ThrowTrajectory flown = throw_peaking_at(20.0);  // 18 m/s^2 needed
  VehicleThrust thrower{pa::kVehicle1, 0.9, 0.0};                      // 0.9 * 20 = 18: enough
  CHECK(admit_vehicles(&flown, thrower, std::nullopt, kSettings).admitted());
  thrower.gain = 0.89;
  const auto a = admit_vehicles(&flown, thrower, std::nullopt, kSettings);
  CHECK(a.refusal == AttemptRefusal::too_weak);
  CHECK(a.why ==
        "vehicle 1 is too weak to throw: thrust gain 0.89 gives 17.8 m/s^2 at most, the throw needs 18.0");
}

TEST_CASE("The catcher is checked only when one catches, against g plus the catch's a_max") {
  const gs::planning::ThrowTrajectory flown = throw_peaking_at(10.0);
  const VehicleThrust thrower{pa::kVehicle1, 1.0, 0.0};
  // 0.9 (9.81 + 4.19) = 12.6 m/s^2 needed: k 0.63 gives exactly 12.6.
  VehicleThrust catcher{pa::kVehicle2, 0.63, 0.0};
  CHECK(admit_vehicles(&flown, thrower, catcher, kSettings).admitted());
  catcher.gain = 0.6;
  const auto a = admit_vehicles(&flown, thrower, catcher, kSettings);
  CHECK(a.refusal == AttemptRefusal::too_weak);
  CHECK(a.why ==
        "vehicle 2 is too weak to catch: thrust gain 0.60 gives 12.0 m/s^2 at most, the catch needs 12.6");
  CHECK(admit_vehicles(&flown, thrower, std::nullopt, kSettings).admitted());
  // The thrower's shortfall is named first.
  const VehicleThrust weak_thrower{pa::kVehicle1, 0.3, 0.0};
  CHECK(admit_vehicles(&flown, weak_thrower, catcher, kSettings).why.find("vehicle 1") == 0);
}

TEST_CASE("A sagging pack lowers the ceiling by (V / V_ref)^2, never raises it") {
  VehicleThrust v{pa::kVehicle1, 0.85, 11.0};
  // 0.85 * (11 / 12.6)^2 * 20 = 12.96 m/s^2 against 0.9 * 17.1 = 15.4.
  CHECK(thrust_shortfall(v, 17.1, "throw", kSettings) ==
        "vehicle 1 is too weak to throw: thrust gain 0.85 at 11.00 V gives 13.0 m/s^2 at most, the throw "
        "needs 15.4");
  v.battery_V = 0.0;  // no voltage reported: k's ceiling alone, 17 m/s^2
  CHECK(thrust_shortfall(v, 17.1, "throw", kSettings).empty());
  // A pack above the reference: k's ceiling (17 m/s^2 against 0.9 * 19 = 17.1 needed), not the
  // 19.5 m/s^2 an uncapped (13.5 / 12.6)^2 would promise.
  v.battery_V = 13.5;
  CHECK(thrust_shortfall(v, 19.0, "throw", kSettings) ==
        "vehicle 1 is too weak to throw: thrust gain 0.85 at 13.50 V gives 17.0 m/s^2 at most, the throw "
        "needs 17.1");
}

TEST_CASE("A pack is spent when its ceiling falls below the margin times the peak, judged by its voltage") {
  // k 1 at 12 V: (12 / 12.6)^2 * 20 = 18.14 m/s^2 against 1.15 * 15.7 = 18.06 (kept) and
  // 1.15 * 15.8 = 18.17 (spent).
  const gs::runtime::PackSwap swap{1.15, 0.95};
  const VehicleThrust v{pa::kVehicle1, 1.0, 12.0};
  CHECK_FALSE(gs::runtime::pack_spent(v, 15.7, swap, kSettings));
  CHECK(gs::runtime::pack_spent(v, 15.8, swap, kSettings));
  // No voltage reported: nothing to judge the pack by, however weak the vehicle.
  CHECK_FALSE(gs::runtime::pack_spent(VehicleThrust{pa::kVehicle1, 0.5, 0.0}, 15.8, swap, kSettings));
}

TEST_CASE("A vehicle short of the margin on a fresh pack swaps once its pack has sagged, not every throw") {
  // k 0.9: a fresh pack gives 18 m/s^2, short of 1.15 * 16 = 18.4; spent below 0.95 * 18 = 17.1,
  // which (V / 12.6)^2 reaches at 12.281 V.
  const gs::runtime::PackSwap swap{1.15, 0.95};
  CHECK_FALSE(gs::runtime::pack_spent(VehicleThrust{pa::kVehicle1, 0.9, 12.6}, 16.0, swap, kSettings));
  CHECK_FALSE(gs::runtime::pack_spent(VehicleThrust{pa::kVehicle1, 0.9, 12.29}, 16.0, swap, kSettings));
  CHECK(gs::runtime::pack_spent(VehicleThrust{pa::kVehicle1, 0.9, 12.27}, 16.0, swap, kSettings));
  // A vehicle that a fresh pack gives the margin keeps to it: k 0.93 (18.6 m/s^2 fresh) is spent at
  // 12.5 V (18.3), above 0.95 of its fresh ceiling.
  CHECK(gs::runtime::pack_spent(VehicleThrust{pa::kVehicle1, 0.93, 12.5}, 16.0, swap, kSettings));
}

TEST_CASE("Of two vehicles the one with the higher ceiling throws, the preferred on a tie") {
  const VehicleThrust strong{pa::kVehicle1, 1.0, 12.0};
  const VehicleThrust weak_pack{pa::kVehicle2, 1.0, 11.0};
  CHECK(thrust_ceiling_mps2(strong, kSettings) == Approx(20.0 * std::pow(12.0 / 12.6, 2.0)));
  CHECK(stronger_thrower(strong, weak_pack, kSettings) == pa::kVehicle1);
  CHECK(stronger_thrower(weak_pack, strong, kSettings) == pa::kVehicle1);
  // A higher gain outweighs a lower voltage when its ceiling is higher: 1.1 (11.5 / 12.6)^2 > (12 / 12.6)^2.
  const VehicleThrust strong_motors{pa::kVehicle2, 1.1, 11.5};
  CHECK(stronger_thrower(strong, strong_motors, kSettings) == pa::kVehicle2);
  const VehicleThrust twin{pa::kVehicle2, 1.0, 12.0};
  CHECK(stronger_thrower(strong, twin, kSettings) == pa::kVehicle1);
  CHECK(stronger_thrower(twin, strong, kSettings) == pa::kVehicle2);
}

TEST_CASE("A point is outside the volume beyond its walls, floor or ceiling, not within its margin") {
  gs::runtime::ArenaVolume volume;
  volume.min_m = Eigen::Vector3d(-2.0, -3.0, 0.0);
  volume.max_m = Eigen::Vector3d(6.0, 3.0, 8.0);
  CHECK_FALSE(gs::runtime::outside_volume(Eigen::Vector3d(0.0, 0.0, 2.0), volume));
  CHECK_FALSE(gs::runtime::outside_volume(Eigen::Vector3d(5.9, 2.9, 7.9), volume));  // in the margin
  CHECK(gs::runtime::outside_volume(Eigen::Vector3d(6.1, 0.0, 2.0), volume));
  CHECK(gs::runtime::outside_volume(Eigen::Vector3d(0.0, -3.1, 2.0), volume));
  CHECK(gs::runtime::outside_volume(Eigen::Vector3d(0.0, 0.0, 8.1), volume));
  CHECK(gs::runtime::outside_volume(Eigen::Vector3d(0.0, 0.0, -0.1), volume));
}
