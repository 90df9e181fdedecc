// The ground station's estimates as the telemetry topics carry them (pa_msgs' VehicleTelemetry on
// rt/pa/vehicle<N>/telemetry, PoleTelemetry on rt/pa/pole/telemetry), and back for a console.
// Stamps are ROS time, as the poses' (ros2_telemetry.hpp). Pure functions.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "groundstation/dds/pa_msgs.hpp"
#include "groundstation/estimation/pole_mode.hpp"
#include "groundstation/estimation/state_estimator.hpp"
#include "groundstation/estimation/vehicle_observer.hpp"
#include "groundstation/link/ground_link.hpp"
#include "groundstation/mission/vehicle_sequencer.hpp"
#include "pa/vehicle_id.hpp"

namespace gs::dds {

// The vehicle's attitude as a quaternion, from the zyx Euler angles of eq. 3.
Eigen::Quaterniond vehicle_attitude(const model::VehicleState& state);

// The DDS topic name of a vehicle's telemetry ("rt/pa/vehicle1/telemetry"); empty for a vehicle
// not in the act.
std::string vehicle_telemetry_topic(pa::VehicleId vehicle);

// unheard until the first heartbeat, then up, or lost while none arrives within the timeout.
std::uint8_t link_state_to_ros(const link::VehicleLinkStatus& status);

// A vehicle's telemetry stamped `stamp_ns`: the link, its task in the mission, the mode it
// reports, and its estimate (estimate_valid false without one): position, velocity, the attitude
// as a quaternion (vehicle_attitude) and the body rates Omega.
VehicleTelemetry vehicle_telemetry_to_ros(pa::VehicleId vehicle, std::int64_t stamp_ns,
                                          const link::VehicleLinkStatus& status, mission::Task task,
                                          const std::optional<estimation::VehicleEstimate>& estimate);

std::uint8_t pole_mode_to_ros(estimation::PoleMode mode);
// None for a value no mode has.
std::optional<estimation::PoleMode> pole_mode_from_ros(std::uint8_t mode);

// Where and when the pole is expected to be caught (the lower end at the catching height).
struct CatchForecast {
  std::int64_t stamp_ns = 0;  // ROS time
  Eigen::Vector3d point_m = Eigen::Vector3d::Zero();
  pa::VehicleId catcher = pa::kVehicle2;
};

// The pole's telemetry stamped `stamp_ns`: its estimate (estimate_valid false until the pole has
// been seen) and the catch forecast, if any.
PoleTelemetry pole_telemetry_to_ros(const estimation::PoleEstimate& pole, std::int64_t stamp_ns,
                                    const std::optional<CatchForecast>& forecast = std::nullopt);
// The pole's state in such a telemetry sample.
model::PoleState pole_state_from_ros(const PoleTelemetry& telemetry);

}  // namespace gs::dds
