// Motion-capture frames between ROS 2's NamedPoseArray and the estimator's frame
// (groundstation/dds/mocap_conversion.hpp): names mapped to bodies as configured, ROS's (x, y, z,
// w) quaternions, and every kind of bad input counted and skipped.
#include "groundstation/dds/mocap_conversion.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <random>
#include <string>
#include <vector>

using gs::dds::MocapBodyNames;
using gs::dds::MocapMessage;
using gs::estimation::MocapFrame;
using gs::estimation::MocapPose;

namespace {

MocapPose pose(double x, double y, double z, const Eigen::Quaterniond& q = Eigen::Quaterniond::Identity()) {
  MocapPose p;
  p.p_m = Eigen::Vector3d(x, y, z);
  p.q = q;
  return p;
}

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

TEST_CASE("Body names default to vehicle1, vehicle2 and pole, and are checked", "[dds]") {
  const MocapBodyNames names;
  CHECK(names.vehicle(pa::kVehicle1) == "vehicle1");
  CHECK(names.vehicle(pa::kVehicle2) == "vehicle2");
  CHECK(names.vehicle(pa::VehicleId(7)).empty());
  CHECK(names.pole == "pole");
  CHECK(gs::dds::check_body_names(names).empty());

  MocapBodyNames same{"cf1", "cf1", "stick"};
  CHECK(gs::dds::check_body_names(same).find("must differ") != std::string::npos);
  MocapBodyNames empty{"cf1", "", "stick"};
  CHECK(gs::dds::check_body_names(empty).find("empty") != std::string::npos);
  MocapBodyNames long_name{std::string(64, 'a'), "cf2", "stick"};
  CHECK(gs::dds::check_body_names(long_name).find("longer than 63") != std::string::npos);
}

TEST_CASE("Times convert to nanoseconds, ROS stamps and back", "[dds]") {
  CHECK(gs::dds::to_nanoseconds(1.005) == 1'005'000'000);
  CHECK(gs::dds::to_nanoseconds(-0.5) == -500'000'000);
  CHECK(gs::dds::to_seconds(1'005'000'000) == Approx(1.005).margin(1e-12));

  const gs::dds::RosTime t = gs::dds::ros_time(1'733'350'000'123'456'789);
  CHECK(t.sec == 1'733'350'000);
  CHECK(t.nanosec == 123'456'789u);
  CHECK(gs::dds::stamp_nanoseconds(t) == 1'733'350'000'123'456'789);
  // Before the epoch (a plant's time is never, but the arithmetic must hold): nanosec stays in range.
  const gs::dds::RosTime before = gs::dds::ros_time(-1'500'000'000);
  CHECK(before.sec == -2);
  CHECK(before.nanosec == 500'000'000u);
  CHECK(gs::dds::stamp_nanoseconds(before) == -1'500'000'000);
}

TEST_CASE("A frame survives the conversion to NamedPoseArray and back, under configured names", "[dds]") {
  MocapFrame frame;
  const Eigen::Quaterniond q1(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()));
  const Eigen::Quaterniond q2(Eigen::AngleAxisd(-0.2, Eigen::Vector3d::UnitX()));
  frame.vehicle[0] = pose(1.0, 2.0, 3.0, q1);
  frame.vehicle[1] = pose(-1.0, 0.5, 1.5, q2);
  frame.pole = pose(0.1, 0.2, 2.5);
  const MocapBodyNames names{"cf7", "cf3", "stick"};

  MocapMessage message;
  gs::dds::mocap_frame_to_dds(frame, 12'345'000'000, names, message);
  const gs::dds::NamedPoseArray& m = message.message();
  CHECK(m.header.stamp.sec == 12);
  CHECK(m.header.stamp.nanosec == 345'000'000u);
  CHECK(std::string(m.header.frame_id) == "world");
  REQUIRE(m.poses._length == 3);
  CHECK(std::string(m.poses._buffer[0].name) == "cf7");
  CHECK(std::string(m.poses._buffer[1].name) == "cf3");
  CHECK(std::string(m.poses._buffer[2].name) == "stick");
  // ROS's quaternion is (x, y, z, w).
  CHECK(m.poses._buffer[0].pose.orientation.w == q1.w());
  CHECK(m.poses._buffer[0].pose.orientation.z == q1.z());
  CHECK(m.poses._buffer[1].pose.orientation.x == q2.x());
  CHECK(m.poses._buffer[0].pose.position.y == 2.0);

  const gs::dds::MocapFrameIn in = gs::dds::mocap_frame_from_dds(m, names);
  CHECK(in.unknown_bodies == 0);
  CHECK(in.invalid_poses == 0);
  CHECK(in.duplicate_bodies == 0);
  CHECK(in.stamp_ns == 12'345'000'000);
  CHECK(in.frame.t_s == Approx(12.345).margin(1e-12));
  REQUIRE(in.frame.vehicle[0]);
  REQUIRE(in.frame.vehicle[1]);
  REQUIRE(in.frame.pole);
  CHECK(in.frame.vehicle[0]->p_m == frame.vehicle[0]->p_m);
  CHECK(in.frame.vehicle[0]->q.isApprox(q1, 1e-14));
  CHECK(in.frame.vehicle[1]->p_m == frame.vehicle[1]->p_m);
  CHECK(in.frame.vehicle[1]->q.isApprox(q2, 1e-14));
  CHECK(in.frame.pole->p_m == frame.pole->p_m);

  // Under the default names the same message is three unknown bodies.
  const auto unnamed = gs::dds::mocap_frame_from_dds(m, MocapBodyNames{});
  CHECK(unnamed.unknown_bodies == 3);
  CHECK(unnamed.first_unknown == "cf7");
  CHECK_FALSE(unnamed.frame.vehicle[0]);
}

TEST_CASE("A body not found is left out, and read back absent", "[dds]") {
  MocapFrame frame;
  frame.vehicle[1] = pose(1.0, 1.0, 1.0);
  MocapMessage message;
  gs::dds::mocap_frame_to_dds(frame, 1'000'000'000, MocapBodyNames{}, message);
  REQUIRE(message.message().poses._length == 1);
  CHECK(std::string(message.message().poses._buffer[0].name) == "vehicle2");

  const auto in = gs::dds::mocap_frame_from_dds(message.message(), MocapBodyNames{});
  CHECK_FALSE(in.frame.vehicle[0]);
  CHECK(in.frame.vehicle[1]);
  CHECK_FALSE(in.frame.pole);
}

TEST_CASE("An empty pose array is a frame with every body absent", "[dds]") {
  gs::dds::NamedPoseArray m{};
  const auto in = gs::dds::mocap_frame_from_dds(m, MocapBodyNames{});
  CHECK_FALSE(in.frame.vehicle[0]);
  CHECK_FALSE(in.frame.vehicle[1]);
  CHECK_FALSE(in.frame.pole);
  CHECK(in.unknown_bodies + in.invalid_poses + in.duplicate_bodies + in.excess_poses == 0);
}

TEST_CASE("Unknown and repeated bodies are counted; the first of a body is kept", "[dds]") {
  MocapMessage message;
  message.clear(0);
  REQUIRE(message.add("dog", pose(9.0, 9.0, 9.0)));
  REQUIRE(message.add("pole", pose(1.0, 0.0, 0.0)));
  REQUIRE(message.add("pole", pose(2.0, 0.0, 0.0)));
  REQUIRE(message.add("Vehicle1", pose(3.0, 0.0, 0.0)));  // names are exact

  const auto in = gs::dds::mocap_frame_from_dds(message.message(), MocapBodyNames{});
  CHECK(in.unknown_bodies == 2);
  CHECK(in.first_unknown == "dog");
  CHECK(in.duplicate_bodies == 1);
  REQUIRE(in.frame.pole);
  CHECK(in.frame.pole->p_m.x() == 1.0);
  CHECK_FALSE(in.frame.vehicle[0]);
}

TEST_CASE("NaN, infinite, zero and non-unit poses are counted and the body left absent", "[dds]") {
  MocapMessage message;
  message.clear(0);
  // motion_capture_tracking's position-only body: a NaN orientation.
  REQUIRE(message.add("vehicle1", pose(1.0, 2.0, 3.0)));
  message.back().pose.orientation = {kNaN, kNaN, kNaN, kNaN};
  REQUIRE(message.add("vehicle2", pose(1.0, 2.0, 3.0)));
  message.back().pose.orientation = {0.0, 0.0, 0.0, 0.0};
  REQUIRE(message.add("pole", pose(kNaN, 0.0, 1.0)));
  auto in = gs::dds::mocap_frame_from_dds(message.message(), MocapBodyNames{});
  CHECK(in.invalid_poses == 3);
  CHECK_FALSE(in.frame.vehicle[0]);
  CHECK_FALSE(in.frame.vehicle[1]);
  CHECK_FALSE(in.frame.pole);

  message.clear(0);
  REQUIRE(message.add("vehicle1", pose(std::numeric_limits<double>::infinity(), 0.0, 0.0)));
  REQUIRE(message.add("vehicle2", pose(0.0, 0.0, 0.0)));
  message.back().pose.orientation = {0.0, 0.0, 0.0, 2.0};  // not a rotation
  REQUIRE(message.add("pole", pose(0.0, 0.0, 1.0)));
  message.back().pose.orientation = {0.0, 0.0, 0.0, 1.0 + 1e-6};  // float rounding: renormalised
  in = gs::dds::mocap_frame_from_dds(message.message(), MocapBodyNames{});
  CHECK(in.invalid_poses == 2);
  CHECK_FALSE(in.frame.vehicle[0]);
  CHECK_FALSE(in.frame.vehicle[1]);
  REQUIRE(in.frame.pole);
  CHECK(in.frame.pole->q.norm() == Approx(1.0).margin(1e-15));
}

TEST_CASE("Overlong and null names are unknown bodies, never read past their bound", "[dds]") {
  std::string long_name(1000, 'p');
  std::vector<gs::dds::NamedPose> poses(2);
  poses[0].name = long_name.data();
  poses[0].pose.orientation.w = 1.0;
  poses[1].name = nullptr;
  gs::dds::NamedPoseArray m{};
  m.poses._buffer = poses.data();
  m.poses._length = 2;
  m.poses._maximum = 2;
  const auto in = gs::dds::mocap_frame_from_dds(m, MocapBodyNames{});
  CHECK(in.unknown_bodies == 2);
  CHECK(in.first_unknown.empty());  // neither is a name worth printing
}

TEST_CASE("Poses beyond the bound are counted and not looked at", "[dds]") {
  std::vector<gs::dds::NamedPose> poses(gs::dds::kMaxPoses + 5);
  std::string other = "other";
  std::string pole = "pole";
  for (auto& p : poses) {
    p.name = other.data();
    p.pose.orientation.w = 1.0;
  }
  poses.back().name = pole.data();  // beyond the bound: never reached
  gs::dds::NamedPoseArray m{};
  m.poses._buffer = poses.data();
  m.poses._length = static_cast<std::uint32_t>(poses.size());
  m.poses._maximum = m.poses._length;
  const auto in = gs::dds::mocap_frame_from_dds(m, MocapBodyNames{});
  CHECK(in.excess_poses == 5);
  CHECK(in.unknown_bodies == gs::dds::kMaxPoses);
  CHECK_FALSE(in.frame.pole);
}

TEST_CASE("A message holds at most its capacity of poses and truncates long names", "[dds]") {
  MocapMessage message;
  message.clear(0);
  const std::string long_name(100, 'x');
  for (std::size_t i = 0; i < MocapMessage::kCapacity; ++i) CHECK(message.add(long_name, MocapPose{}));
  CHECK_FALSE(message.add("pole", MocapPose{}));
  CHECK(message.message().poses._length == MocapMessage::kCapacity);
  CHECK(std::strlen(message.message().poses._buffer[0].name) == gs::dds::kMaxBodyName);
}

TEST_CASE("Any pose array converts without trusting a bad pose, and every pose is accounted for", "[dds]") {
  // Seeded random arrays: names known, unknown, repeated, overlong and null; positions and
  // quaternions finite, NaN, infinite, huge, zero or off unit. Whatever comes in, what reaches
  // the estimator is finite with a unit quaternion, and each pose is counted exactly once.
  std::mt19937_64 random(26);
  const std::vector<std::string> pool = {
      "vehicle1",           "vehicle2",           "pole", "wand", "", std::string(63, 'v'),
      std::string(64, 'v'), std::string(300, 'p')};
  const double specials[] = {
      0.0, -0.0, 1.0, -1.0, 1e308, -1e308, 1e-310, kNaN, std::numeric_limits<double>::infinity()};
  const auto value = [&]() {
    std::uniform_int_distribution<int> pick(0, 3);
    if (pick(random) == 0) return specials[std::uniform_int_distribution<std::size_t>(0, 8)(random)];
    return std::uniform_real_distribution<double>(-2.0, 2.0)(random);
  };
  for (int trial = 0; trial < 2000; ++trial) {
    const std::size_t length = std::uniform_int_distribution<std::size_t>(0, gs::dds::kMaxPoses + 8)(random);
    std::vector<std::string> names(length);
    std::vector<gs::dds::NamedPose> poses(length);
    for (std::size_t i = 0; i < length; ++i) {
      names[i] = pool[std::uniform_int_distribution<std::size_t>(0, pool.size() - 1)(random)];
      poses[i].name = std::uniform_int_distribution<int>(0, 20)(random) == 0 ? nullptr : names[i].data();
      poses[i].pose.position = {value(), value(), value()};
      if (std::uniform_int_distribution<int>(0, 1)(random) == 0) {
        // A unit quaternion, as a camera system sends it, perhaps rounded.
        Eigen::Quaterniond q(Eigen::Vector4d(value(), value(), value(), value()));
        if (!std::isfinite(q.norm()) || q.norm() == 0.0) q = Eigen::Quaterniond::Identity();
        q.normalize();
        poses[i].pose.orientation = {q.x(), q.y(), q.z(), q.w() * (1.0 + 1e-7)};
      } else {
        poses[i].pose.orientation = {value(), value(), value(), value()};
      }
    }
    gs::dds::NamedPoseArray m{};
    m.poses._buffer = poses.data();
    m.poses._length = static_cast<std::uint32_t>(length);
    m.poses._maximum = m.poses._length;
    m.header.stamp =
        gs::dds::ros_time(std::uniform_int_distribution<std::int64_t>(-(1LL << 62), 1LL << 62)(random));

    const gs::dds::MocapFrameIn in = gs::dds::mocap_frame_from_dds(m, MocapBodyNames{});
    std::size_t valid = 0;
    const auto check_pose = [&](const std::optional<MocapPose>& p) {
      if (!p) return;
      ++valid;
      CHECK(p->p_m.allFinite());
      CHECK(std::abs(p->q.norm() - 1.0) < 1e-12);
    };
    check_pose(in.frame.vehicle[0]);
    check_pose(in.frame.vehicle[1]);
    check_pose(in.frame.pole);
    CHECK(valid + in.unknown_bodies + in.invalid_poses + in.duplicate_bodies + in.excess_poses == length);
    CHECK(in.excess_poses == (length > gs::dds::kMaxPoses ? length - gs::dds::kMaxPoses : 0));
  }
}
