// The poses the Fast DDS peer publishes in frame k (fastdds_peer.cpp) and the tests expect
// (fastdds_interop_test.cpp): one definition for both ends, with no DDS in it, so that the test
// checks every field bit for bit. Body 0 is vehicle 1, 1 vehicle 2, 2 the pole. Quaternions are
// ROS's (x, y, z, w).
#pragma once

#include <array>
#include <cmath>
#include <limits>

namespace fastdds_test {

inline constexpr const char* kUnknownBody = "wand";
inline constexpr const char* kPositionOnlyBody = "single_marker";

struct Pose {
  std::array<double, 3> position;
  std::array<double, 4> orientation_xyzw;
};

// A rotation by `angle_rad` about the unit axis (ax, ay, az).
inline std::array<double, 4> rotation(double ax, double ay, double az, double angle_rad) {
  const double s = std::sin(0.5 * angle_rad);
  return {ax * s, ay * s, az * s, std::cos(0.5 * angle_rad)};
}

inline Pose pose(int body, long k) {
  const double t = 0.001 * static_cast<double>(k);
  switch (body) {
    case 0: return {{1.0 + t, -2.0, 0.5 + 0.5 * t}, rotation(0.0, 0.0, 1.0, 0.01 * static_cast<double>(k))};
    case 1: return {{-1.0, 2.0 + t, 1.0}, rotation(1.0, 0.0, 0.0, 0.3)};
    default: return {{0.25, -0.5, 2.0 + t}, rotation(0.0, 1.0, 0.0, -0.1)};
  }
}

// The frame number a vehicle 1 pose was made for (its x is 1 + k / 1000).
inline long frame_of(double vehicle1_x) { return std::lround((vehicle1_x - 1.0) * 1000.0); }

// motion_capture_tracking's position-only body: a NaN orientation.
inline Pose position_only(long k) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  return {{0.0, 0.0, 0.001 * static_cast<double>(k)}, {nan, nan, nan, nan}};
}

}  // namespace fastdds_test
