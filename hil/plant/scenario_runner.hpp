// Runs a scenario on the truth plant in memory and returns what the motion capture delivered,
// the true states and the IMU samples: the data behind `hil record`, and what the estimator's
// tests compare against.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "hil/plant/imu.hpp"
#include "hil/plant/plant.hpp"
#include "hil/plant/scenario.hpp"

namespace hil {

// One body in one motion-capture frame (a body lost in the frame has no row).
struct MocapRow {
  double t_s = 0.0;          // when the frame reached the ground station (capture + latency)
  double capture_t_s = 0.0;  // when the pose was true
  Body body = Body::pole;
  Vec3 position_m = Vec3::Zero();
  Quat attitude = Quat::Identity();  // body -> inertial, w >= 0; for the pole body z is n
};

// The true pole at one plant tick: centre of mass, its velocity, the axis n, the angular
// velocity (inertial frame) and what the pole touches.
struct PoleTruthRow {
  double t_s = 0.0;
  Vec3 position_m = Vec3::Zero();
  Vec3 velocity_mps = Vec3::Zero();
  Vec3 axis = Vec3::UnitZ();
  Vec3 rate_radps = Vec3::Zero();
  Contact contact = Contact::none;
};

struct VehicleTruthRow {
  double t_s = 0.0;
  pa::VehicleId vehicle = pa::kVehicle1;
  VehicleState state{};
};

struct ScenarioResult {
  PlantConfig config{};  // the plant as run (randomised if the scenario asked for it)
  double tick_s = 0.0;   // the plant tick (the IMU period); truth rows come at this rate
  std::vector<MocapRow> mocap;
  std::vector<PoleTruthRow> pole_truth;
  std::vector<VehicleTruthRow> vehicle_truth;
  std::array<std::vector<ImuSample>, 2> imu;
  std::vector<PoleContactEvent> contact_events;
  std::optional<double> launch_t_s;  // the pole leaves the thrower (or its plate)
  std::optional<double> impact_t_s;  // a pole end first lands on a plate after that
  Contact impact_on = Contact::none;
  int impact_end = -1;
  std::optional<Vec3> catch_position_m;  // where an auto-placed vehicle was put
};

// Runs the scenario. Returns false with a message if it cannot be set up (e.g. an auto-placed
// catcher for a pole that never comes down to the catch height); never throws.
bool run_scenario(const Scenario& scenario, ScenarioResult& out, std::string& error);

// The pole's launch state for a launch scenario (at launch_time_s).
PoleState launch_state(const Scenario& scenario);

}  // namespace hil
