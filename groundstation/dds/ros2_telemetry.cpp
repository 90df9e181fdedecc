#include "groundstation/dds/ros2_telemetry.hpp"

#include <Eigen/Geometry>

#include "groundstation/dds/mocap_conversion.hpp"
#include "groundstation/dds/telemetry_conversion.hpp"

namespace gs::dds {
namespace {

PoseStamped pose_stamped(const Eigen::Vector3d& p, const Eigen::Quaterniond& q, std::int64_t stamp_ns) {
  PoseStamped out{};
  out.header.stamp = ros_time(stamp_ns);
  // A C string field of the generated struct; Cyclone only reads it when writing.
  out.header.frame_id = const_cast<char*>(kWorldFrame.data());
  out.pose.position = {p.x(), p.y(), p.z()};
  out.pose.orientation = {q.x(), q.y(), q.z(), q.w()};  // ROS: (x, y, z, w)
  return out;
}

}  // namespace

std::string vehicle_pose_topic(pa::VehicleId vehicle) {
  if (!pa::is_act_vehicle(vehicle)) return {};
  return "rt/pa/vehicle" + std::to_string(vehicle.node()) + "/pose";
}

PoseStamped vehicle_pose_to_ros(const estimation::VehicleEstimate& estimate, std::int64_t stamp_ns) {
  return pose_stamped(estimate.state.p_m, vehicle_attitude(estimate.state), stamp_ns);
}

PoseStamped pole_pose_to_ros(const model::PoleState& pole, std::int64_t stamp_ns) {
  const Eigen::Quaterniond q = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), pole.n);
  return pose_stamped(pole.p_m, q, stamp_ns);
}

}  // namespace gs::dds
