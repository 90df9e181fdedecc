// Motion-capture frames between the pa_mocap message and the estimator's frame
// (groundstation/dds/mocap_conversion.hpp).
#include "groundstation/dds/mocap_conversion.hpp"

#include <catch2/catch.hpp>
#include <cstring>
#include <string>

using gs::dds::MocapMessage;
using gs::estimation::MocapFrame;
using gs::estimation::MocapPose;

namespace {

MocapPose pose(double x, double y, double z, const Eigen::Quaterniond& q) {
  MocapPose p;
  p.p_m = Eigen::Vector3d(x, y, z);
  p.q = q;
  return p;
}

}  // namespace

TEST_CASE("Vehicle body names follow the vehicle id", "[dds]") {
  CHECK(gs::dds::vehicle_body_name(pa::kVehicle1) == "vehicle1");
  CHECK(gs::dds::vehicle_body_name(pa::kVehicle2) == "vehicle2");
  CHECK(gs::dds::vehicle_body_name(pa::VehicleId(7)).empty());
}

TEST_CASE("Times convert to nanoseconds and back", "[dds]") {
  CHECK(gs::dds::to_nanoseconds(1.005) == 1'005'000'000);
  CHECK(gs::dds::to_nanoseconds(-0.5) == -500'000'000);
  CHECK(gs::dds::to_seconds(1'005'000'000) == Approx(1.005).margin(1e-12));
}

TEST_CASE("A frame survives the conversion to the message and back", "[dds]") {
  MocapFrame frame;
  frame.t_s = 12.345;
  const Eigen::Quaterniond q1(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()));
  const Eigen::Quaterniond q2(Eigen::AngleAxisd(-0.2, Eigen::Vector3d::UnitX()));
  frame.vehicle[0] = pose(1.0, 2.0, 3.0, q1);
  frame.vehicle[1] = pose(-1.0, 0.5, 1.5, q2);
  frame.pole = pose(0.1, 0.2, 2.5, Eigen::Quaterniond::Identity());

  MocapMessage message;
  gs::dds::mocap_frame_to_dds(frame, 42, message);
  const pa_arena_MocapFrame& m = message.message();
  CHECK(m.frame_number == 42);
  CHECK(m.capture_time_ns == 12'345'000'000);
  REQUIRE(m.bodies._length == 3);
  CHECK(std::string(m.bodies._buffer[0].name) == "vehicle1");
  CHECK(std::string(m.bodies._buffer[1].name) == "vehicle2");
  CHECK(std::string(m.bodies._buffer[2].name) == "pole");
  CHECK(m.bodies._buffer[0].attitude.w == q1.w());
  CHECK(m.bodies._buffer[0].attitude.z == q1.z());

  const gs::dds::MocapFrameIn in = gs::dds::mocap_frame_from_dds(m);
  CHECK(in.unknown_bodies == 0);
  CHECK(in.duplicate_bodies == 0);
  CHECK(in.frame.t_s == Approx(12.345).margin(1e-12));
  REQUIRE(in.frame.vehicle[0]);
  REQUIRE(in.frame.vehicle[1]);
  REQUIRE(in.frame.pole);
  CHECK(in.frame.vehicle[0]->p_m == frame.vehicle[0]->p_m);
  CHECK(in.frame.vehicle[0]->q.coeffs() == q1.coeffs());
  CHECK(in.frame.vehicle[1]->p_m == frame.vehicle[1]->p_m);
  CHECK(in.frame.vehicle[1]->q.coeffs() == q2.coeffs());
  CHECK(in.frame.pole->p_m == frame.pole->p_m);
}

TEST_CASE("An absent body is published untracked and read back absent", "[dds]") {
  MocapFrame frame;
  frame.t_s = 1.0;
  frame.vehicle[1] = pose(1.0, 1.0, 1.0, Eigen::Quaterniond::Identity());

  MocapMessage message;
  gs::dds::mocap_frame_to_dds(frame, 1, message);
  REQUIRE(message.message().bodies._length == 3);
  CHECK_FALSE(message.message().bodies._buffer[0].tracked);
  CHECK(message.message().bodies._buffer[1].tracked);
  CHECK_FALSE(message.message().bodies._buffer[2].tracked);

  const auto in = gs::dds::mocap_frame_from_dds(message.message());
  CHECK_FALSE(in.frame.vehicle[0]);
  CHECK(in.frame.vehicle[1]);
  CHECK_FALSE(in.frame.pole);
}

TEST_CASE("Unknown and repeated bodies are counted; the first of a body is kept", "[dds]") {
  MocapMessage message;
  message.clear(7, 0);
  REQUIRE(message.add("dog", pose(9.0, 9.0, 9.0, Eigen::Quaterniond::Identity())));
  REQUIRE(message.add("pole", pose(1.0, 0.0, 0.0, Eigen::Quaterniond::Identity())));
  REQUIRE(message.add("pole", pose(2.0, 0.0, 0.0, Eigen::Quaterniond::Identity())));
  REQUIRE(message.add("Vehicle1", pose(3.0, 0.0, 0.0, Eigen::Quaterniond::Identity())));  // names are exact

  const auto in = gs::dds::mocap_frame_from_dds(message.message());
  CHECK(in.unknown_bodies == 2);
  CHECK(in.duplicate_bodies == 1);
  REQUIRE(in.frame.pole);
  CHECK(in.frame.pole->p_m.x() == 1.0);
  CHECK_FALSE(in.frame.vehicle[0]);
}

TEST_CASE("A message holds at most the IDL's bound of bodies and truncates long names", "[dds]") {
  MocapMessage message;
  message.clear(1, 0);
  const std::string long_name(100, 'x');
  for (unsigned i = 0; i < pa_arena_kMaxBodies; ++i) CHECK(message.add(long_name, MocapPose{}));
  CHECK_FALSE(message.add("pole", MocapPose{}));
  CHECK(message.message().bodies._length == pa_arena_kMaxBodies);
  CHECK(std::strlen(message.message().bodies._buffer[0].name) == pa_arena_kMaxBodyName);
}

TEST_CASE("A name that fills its array is not read past its end", "[dds]") {
  pa_arena_RigidBody body{};
  std::memset(body.name, 'p', sizeof body.name);  // no terminator
  body.tracked = true;
  pa_arena_MocapFrame m{};
  m.bodies._buffer = &body;
  m.bodies._length = 1;
  m.bodies._maximum = 1;
  const auto in = gs::dds::mocap_frame_from_dds(m);
  CHECK(in.unknown_bodies == 1);
}
