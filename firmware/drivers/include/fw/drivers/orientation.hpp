// How a sensor is mounted on the board: each body axis (x forward, y left, z up, as in
// fw/mixer.hpp) is one sensor axis, possibly negated. Only such signed permutations are
// allowed (a chip sits square on a board), so applying one is exact and costs no maths.
#pragma once

#include <array>
#include <cstdint>

#include "fw/types.hpp"

namespace fw::drivers {

struct AxisMap {
  std::array<std::uint8_t, 3> sensor_axis{0, 1, 2};  // body axis i reads sensor axis sensor_axis[i] ...
  std::array<std::int8_t, 3> sign{1, 1, 1};          // ... times sign[i]
};

// A proper rotation: every sensor axis used once, signs of +-1, determinant +1 (a mirror
// image would turn a right-handed sensor into a left-handed body frame).
constexpr bool is_rotation(const AxisMap& m) {
  bool used[3] = {false, false, false};
  for (int i = 0; i < 3; ++i) {
    if (m.sensor_axis[i] > 2 || used[m.sensor_axis[i]]) return false;
    if (m.sign[i] != 1 && m.sign[i] != -1) return false;
    used[m.sensor_axis[i]] = true;
  }
  // The permutation's parity times the signs' product.
  int inversions = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = i + 1; j < 3; ++j)
      if (m.sensor_axis[i] > m.sensor_axis[j]) ++inversions;
  const int parity = inversions % 2 == 0 ? 1 : -1;
  return parity * m.sign[0] * m.sign[1] * m.sign[2] == 1;
}

constexpr Vec3f to_body(const AxisMap& m, const Vec3f& sensor) {
  Vec3f body{};
  for (int i = 0; i < 3; ++i) body[i] = m.sign[i] > 0 ? sensor[m.sensor_axis[i]] : -sensor[m.sensor_axis[i]];
  return body;
}

// Betaflight's `gyro_1_sensor_align` values CW0..CW270: the chip turned clockwise (seen from
// above) about the board's z axis by 0, 90, 180 or 270 degrees. A chip turned by a reads a
// body vector turned by -a, so body = Rz(-a) sensor.
inline constexpr AxisMap kCw0{{0, 1, 2}, {1, 1, 1}};
inline constexpr AxisMap kCw90{{1, 0, 2}, {1, -1, 1}};
inline constexpr AxisMap kCw180{{0, 1, 2}, {-1, -1, 1}};
inline constexpr AxisMap kCw270{{1, 0, 2}, {-1, 1, 1}};
static_assert(is_rotation(kCw0) && is_rotation(kCw90) && is_rotation(kCw180) && is_rotation(kCw270));

}  // namespace fw::drivers
