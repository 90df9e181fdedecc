// Small value types shared by the firmware core modules. No heap, no exceptions.
#pragma once

#include <array>
#include <cstdint>

namespace fw {

using Vec3f = std::array<float, 3>;       // x, y, z (body frame unless a name says otherwise)
using Motors = std::array<float, 4>;      // one value per motor, order in mixer.hpp
using Quaternion = std::array<float, 4>;  // w, x, y, z; rotates body vectors into the inertial frame

// One IMU sample: the event that runs the 1 kHz loop.
struct ImuSample {
  std::uint32_t t_us = 0;  // vehicle clock
  Vec3f gyro_radps{};      // body rates
  Vec3f accel_mps2{};      // specific force in the body frame (reads +g on z when level at rest)
};

// Saturation flags reported by the mixer, one bit per axis and direction. The rate
// controller freezes each integrator in the direction its axis is saturated (PX4 style).
namespace saturation {
inline constexpr std::uint8_t roll_pos = 1u << 0;
inline constexpr std::uint8_t roll_neg = 1u << 1;
inline constexpr std::uint8_t pitch_pos = 1u << 2;
inline constexpr std::uint8_t pitch_neg = 1u << 3;
inline constexpr std::uint8_t yaw_pos = 1u << 4;
inline constexpr std::uint8_t yaw_neg = 1u << 5;
inline constexpr std::uint8_t collective_high = 1u << 6;
inline constexpr std::uint8_t collective_low = 1u << 7;

constexpr std::uint8_t positive(int axis) { return static_cast<std::uint8_t>(1u << (2 * axis)); }
constexpr std::uint8_t negative(int axis) { return static_cast<std::uint8_t>(1u << (2 * axis + 1)); }
}  // namespace saturation

}  // namespace fw
