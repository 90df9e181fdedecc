// Where an attempt flies (groundstation/runtime/throw_geometry.hpp): the two throwers' frames
// facing each other, the catch point and height from the adaptation in the throw's frame or
// from a target's aim, and the thrower's start below the origin by the plate's height.
#include <catch2/catch.hpp>

#include <cmath>

#include "groundstation/runtime/throw_geometry.hpp"
#include "pa/constants.hpp"

namespace {

using namespace gs::runtime;

gs::adaptation::AdaptationState adapted() {
  gs::adaptation::AdaptationState a;
  a.catch_height_m = -0.4;
  a.waiting_xy_m = Eigen::Vector2d(2.0, 0.1);
  a.offset_bias_m = Eigen::Vector2d(0.05, -0.02);
  a.bias_samples = 5;
  return a;
}

const Eigen::Vector3d kOrigin(1.0, -1.0, 2.0);

}  // namespace

TEST_CASE("Vehicle 1 throws from the origin; vehicle 2 back from where vehicle 1's throws come down") {
  const gs::control::ThrowFrame first = throw_frame_of(pa::kVehicle1, kOrigin, M_PI / 2, adapted());
  CHECK(first.origin_m == kOrigin);
  CHECK(first.yaw_rad == M_PI / 2);
  const gs::control::ThrowFrame second = throw_frame_of(pa::kVehicle2, kOrigin, M_PI / 2, adapted());
  // +x of vehicle 1's frame is the arena's +y: its catch point 2 m along it, 0.1 m to its left.
  CHECK(second.origin_m.x() == Approx(1.0 - 0.1));
  CHECK(second.origin_m.y() == Approx(-1.0 + 2.0));
  CHECK(second.origin_m.z() == 2.0);
  CHECK(second.yaw_rad == Approx(M_PI / 2 + M_PI));
}

TEST_CASE("The catch point and height: the adapted ones in the throw's frame, or the target aimed at") {
  const gs::control::ThrowFrame frame{kOrigin, 0.0};
  const gs::adaptation::AdaptationState a = adapted();
  const Eigen::Vector2d xy = catch_point_xy(frame, a, std::nullopt);
  const Eigen::Vector2d compensated = gs::adaptation::compensate_offset_bias(a.waiting_xy_m, a);
  CHECK(compensated != a.waiting_xy_m);  // the bias counts
  CHECK(xy.x() == Approx(1.0 + compensated.x()));
  CHECK(xy.y() == Approx(-1.0 + compensated.y()));
  CHECK(catch_height_m(frame, a, std::nullopt, 0.02) == Approx(2.0 - 0.4 + 0.02));
  const Eigen::Vector3d aim(4.0, 3.0, 1.5);
  CHECK(catch_point_xy(frame, a, aim) == aim.head<2>());
  CHECK(catch_height_m(frame, a, aim, 0.02) == Approx(1.52));
}

TEST_CASE("The thrower starts with its plate's centre at the origin") {
  const Eigen::Vector3d start = throw_start_m({kOrigin, 0.3});
  CHECK(start.head<2>() == kOrigin.head<2>());
  CHECK(start.z() == Approx(2.0 - pa::kPlateHeightAboveCg_m));
}
