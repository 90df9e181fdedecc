// A scenario for the recorder: where the vehicles are and how they are flown, how the pole
// starts, how long to run, which plant configuration and seed. Read from a YAML file
// (hil/config/scenarios/*.yaml documents every key); every error names the file and line.
//
// The vehicles are flown by the runner's own controllers acting on the TRUE plant state
// (vehicle_controller.hpp, pole_balancer.hpp): scenarios generate test data for the estimator
// and the planners, they are not the ground station.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "hil/plant/plant_config.hpp"
#include "hil/plant/types.hpp"
#include "pa/vehicle_id.hpp"

namespace hil {

enum class VehicleMode : std::uint8_t {
  parked,   // on the floor, motors off
  hold,     // hovering at its position
  balance,  // hovering at its position and balancing the pole while the pole is on its plate
  // pole_start = launch only: until the launch the vehicle carries the pole's lower end on its
  // plate (moved with it, level, motors off: a stand-in for the throw manoeuvre, whose last
  // instant has no force between plate and pole); it keeps its motors off for
  // thrower_release_s after the launch, falling away from the pole, then holds its position.
  // Its IMU means nothing before the launch.
  thrower,
};

struct ScenarioVehicle {
  VehicleMode mode = VehicleMode::parked;
  Vec3 position_m = Vec3::Zero();  // for parked vehicles only x and y count
  // true: placed under the point where the pole's lowest end comes down through
  // catch_height_m (found by flying the launched pole alone in the same plant first).
  bool position_auto = false;
  double yaw_rad = 0.0;
  // What the vehicle does once the pole lands on its plate.
  VehicleMode after_catch = VehicleMode::hold;
};

enum class PoleStart : std::uint8_t {
  launch,    // moving with the launch state until launch_time_s, free from then on
  balanced,  // standing on a vehicle's plate
};

enum class LaunchReference : std::uint8_t { lower_end, centre };

struct Scenario {
  std::string name;
  std::string source;  // the file it came from, for messages
  double duration_s = 3.0;
  std::uint64_t seed = 1;
  bool randomise = false;
  PlantConfig plant{};  // plant_config file (or the defaults) with the plant.* overrides applied
  std::array<ScenarioVehicle, 2> vehicle{};
  PoleStart pole_start = PoleStart::launch;

  // pole_start = launch. The launch state: the pole's lower end (or centre) position and
  // velocity, its tilt alpha from the vertical towards the heading direction (cos h, sin h, 0),
  // and the tilt rate. Before launch_time_s the pole moves with that velocity and rate unaccelerated
  // (as if carried by the thrower); from then on it flies freely.
  double launch_time_s = 0.2;
  LaunchReference launch_reference = LaunchReference::lower_end;
  Vec3 pole_position_m = Vec3(1.5, 0.0, 2.03);
  Vec3 pole_velocity_mps = Vec3(0.3, 0.0, 5.5);
  double pole_tilt_rad = 0.48;
  double pole_tilt_rate_radps = 2.5;
  double pole_tilt_heading_rad = 0.0;
  double thrower_release_s = 0.1;      // motors off after the launch (VehicleMode::thrower)
  double catch_height_m = 1.343;       // plate surface height for position_auto
  Vec3 catch_offset_m = Vec3::Zero();  // added to the auto position (x, y; z ignored)

  // pole_start = balanced.
  pa::VehicleId balance_vehicle = pa::kVehicle1;
  double balance_tilt_rad = 0.02;     // initial tilt towards +x
  double balance_lambda_radps = 3.0;  // balancer closed-loop roots (pole_balancer.hpp)
};

// Parses scenario text. `name` is used in messages; `base_dir` resolves a relative
// plant_config path. Returns false with "name:line: message" on any error; never throws.
bool parse_scenario(std::string_view text, const std::string& name, const std::string& base_dir,
                    Scenario& out, std::string& error);
bool load_scenario(const std::string& path, Scenario& out, std::string& error);

// The scenario files in the source tree.
std::string scenario_directory();

}  // namespace hil
