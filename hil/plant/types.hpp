// Value types of the truth plant: the true states of the two vehicles and the pole, the motor
// commands that drive the vehicles, and the names of the bodies and contacts.
//
// Frames: the inertial frame has z up and gravity along -z (docs/architecture.md, "Conventions"). A
// vehicle's body frame has x forward, y left, z up (thrust and plate normal along +z), as in
// firmware/core/include/fw/mixer.hpp. The pole's body frame has its z-axis along the pole: the
// unit vector n of the paper (Section II-B) is the body z-axis expressed in the inertial frame.
// Quaternions rotate body vectors into the inertial frame.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <string_view>

namespace hil {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;

// Normalised motor commands, one per motor in the firmware's order (fw/mixer.hpp: 0 front-right,
// 1 rear-left, 2 front-left, 3 rear-right), 0..1 and linear in thrust: command 1 asks for the
// motor's maximum thrust. This is what HIL_MOTORS frames carry. Out-of-range values are clamped;
// a non-finite command stops that motor (an ESC that cannot read its signal does not spin).
struct MotorCommands {
  std::array<double, 4> command{};
};

// A rigid body: the centre of mass in the inertial frame, its velocity, the attitude and the
// angular velocity in the body frame.
struct RigidBodyState {
  Vec3 position_m = Vec3::Zero();
  Vec3 velocity_mps = Vec3::Zero();
  Quat attitude = Quat::Identity();  // body -> inertial
  Vec3 rate_body_radps = Vec3::Zero();

  Mat3 rotation() const { return attitude.toRotationMatrix(); }
  Vec3 rate_inertial_radps() const { return attitude * rate_body_radps; }
  // Inertial velocity of a point given in body coordinates relative to the centre of mass.
  Vec3 point_velocity_mps(const Vec3& r_body_m) const {
    return velocity_mps + attitude * rate_body_radps.cross(r_body_m);
  }
};

struct VehicleState {
  RigidBodyState body;
  std::array<double, 4> motor_thrust_N{};  // the thrust each motor produces now (after its lag)
};

// The pole: a rod whose centre of mass is body.position_m and whose axis is the body z-axis.
// A point s along n from the centre of mass lies at p + s n (the ends: PoleConfig).
struct PoleState {
  RigidBodyState body;

  Vec3 axis() const { return body.attitude * Vec3::UnitZ(); }  // n
  Vec3 point_m(double along_axis_m) const { return body.position_m + along_axis_m * axis(); }
};

// The three bodies the motion capture sees.
enum class Body : std::uint8_t { vehicle1 = 0, vehicle2 = 1, pole = 2 };
inline constexpr std::string_view body_name(Body b) {
  return b == Body::vehicle1 ? "vehicle1" : b == Body::vehicle2 ? "vehicle2" : "pole";
}

// What a pole end (or the pole as a whole) is touching.
enum class Contact : std::uint8_t { none = 0, vehicle1 = 1, vehicle2 = 2, floor = 3 };
inline constexpr std::string_view contact_name(Contact c) {
  switch (c) {
    case Contact::vehicle1: return "vehicle1";
    case Contact::vehicle2: return "vehicle2";
    case Contact::floor: return "floor";
    case Contact::none: break;
  }
  return "none";
}

// The surfaces a point can touch: a vehicle's catching plate or the floor.
enum class Surface : std::uint8_t { plate1 = 0, plate2 = 1, floor = 2 };
inline constexpr Contact contact_of(Surface s) {
  return s == Surface::plate1 ? Contact::vehicle1 : s == Surface::plate2 ? Contact::vehicle2 : Contact::floor;
}

}  // namespace hil
