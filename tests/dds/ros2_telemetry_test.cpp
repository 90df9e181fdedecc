// The ground station's estimates as ROS 2 PoseStamped (groundstation/dds/ros2_telemetry.hpp):
// the topic names ROS 2 tools subscribe to, ROS's (x, y, z, w) quaternion order, the world frame,
// the stamp, and the pole's axis as the pose's z-axis.
#include "groundstation/dds/ros2_telemetry.hpp"

#include <catch2/catch.hpp>
#include <string>

#include "groundstation/dds/telemetry_conversion.hpp"

TEST_CASE("The pose topics are ROS 2's /pa/<body>/pose on DDS", "[dds]") {
  CHECK(gs::dds::vehicle_pose_topic(pa::kVehicle1) == "rt/pa/vehicle1/pose");
  CHECK(gs::dds::vehicle_pose_topic(pa::kVehicle2) == "rt/pa/vehicle2/pose");
  CHECK(gs::dds::vehicle_pose_topic(pa::VehicleId(9)).empty());
  CHECK(std::string(gs::dds::kPolePoseTopic) == "rt/pa/pole/pose");
  CHECK(std::string(geometry_msgs_msg_dds__PoseStamped__desc.m_typename) ==
        "geometry_msgs::msg::dds_::PoseStamped_");
}

TEST_CASE("A vehicle's estimate is a PoseStamped in the world frame, w last", "[dds]") {
  gs::estimation::VehicleEstimate e;
  e.state.p_m = Eigen::Vector3d(1.0, -2.0, 3.0);
  e.state.phi_rad = 0.1;
  e.state.theta_rad = -0.2;
  e.state.psi_rad = 0.3;
  const gs::dds::PoseStamped pose = gs::dds::vehicle_pose_to_ros(e, 1'733'350'000'250'000'000);
  CHECK(std::string(pose.header.frame_id) == "world");
  CHECK(pose.header.stamp.sec == 1'733'350'000);
  CHECK(pose.header.stamp.nanosec == 250'000'000u);
  CHECK(pose.pose.position.x == 1.0);
  CHECK(pose.pose.position.y == -2.0);
  CHECK(pose.pose.position.z == 3.0);
  const Eigen::Quaterniond q = gs::dds::vehicle_attitude(e.state);
  CHECK(pose.pose.orientation.x == q.x());
  CHECK(pose.pose.orientation.y == q.y());
  CHECK(pose.pose.orientation.z == q.z());
  CHECK(pose.pose.orientation.w == q.w());
  // The same orientation the vehicle's telemetry carries.
  const auto telemetry = gs::dds::vehicle_telemetry_to_ros(pa::kVehicle1, 0, gs::link::VehicleLinkStatus{},
                                                           gs::mission::Task::hover, e);
  CHECK(telemetry.orientation.w == q.w());
  CHECK(telemetry.orientation.x == q.x());
}

TEST_CASE("The pole's pose turns z onto its axis", "[dds]") {
  gs::model::PoleState pole;
  pole.p_m = Eigen::Vector3d(0.5, 0.0, 2.0);
  pole.n = Eigen::Vector3d(0.3, -0.4, 1.0).normalized();
  const gs::dds::PoseStamped pose = gs::dds::pole_pose_to_ros(pole, 0);
  const Eigen::Quaterniond q(pose.pose.orientation.w, pose.pose.orientation.x, pose.pose.orientation.y,
                             pose.pose.orientation.z);
  CHECK(q.norm() == Approx(1.0).margin(1e-12));
  CHECK((q * Eigen::Vector3d::UnitZ() - pole.n).norm() < 1e-12);
  CHECK(pose.pose.position.z == 2.0);
}
