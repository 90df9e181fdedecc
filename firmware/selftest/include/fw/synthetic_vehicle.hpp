// A small rigid-body quadrocopter for the self-test: motor lag, thrust and torques from the
// motor commands, rigid-body rotation, gravity, a floor, an external force pulse (the pole
// landing on the plate), and an IMU read from its motion. It is the firmware's sparring
// partner on the MCU, where the HIL plant does not exist; it is not the HIL truth plant.
// Float, no heap.
#pragma once

#include <cstdint>

#include "fw/config.hpp"
#include "fw/mixer.hpp"
#include "fw/types.hpp"
#include "pa/constants.hpp"

namespace fw::selftest {

class SyntheticVehicle {
 public:
  explicit SyntheticVehicle(const AirframeConfig& airframe);

  // Advance by dt with the given normalised motor commands (zero when off) and an external
  // force on the vehicle in the inertial frame (N). A small constant torque (a centre of
  // gravity slightly off the thrust axis) acts in flight, so the rate loop's integrators work.
  void step(const Motors& command, const Vec3f& external_force_N, float dt_s);

  // The IMU sample at the current state (deterministic pseudo-noise of a few mrad/s).
  ImuSample imu(std::uint32_t t_us);

  const Vec3f& position_m() const { return p_; }
  const Vec3f& velocity_mps() const { return v_; }
  const Vec3f& rate_radps() const { return w_; }
  bool on_floor() const { return on_floor_; }
  // Cosine of the tilt of the body z-axis from the vertical, and inertial up in the body frame.
  float tilt_cos() const;
  Vec3f up_in_body() const;

 private:
  float noise();

  AirframeConfig airframe_;
  Mixer geometry_;
  Vec3f p_{};
  Vec3f v_{};
  Quaternion q_{1, 0, 0, 0};  // body to inertial
  Vec3f w_{};                 // body rates
  Motors thrust_N_{};
  Vec3f specific_force_body_{0, 0, pa::kGravityFloat_mps2};
  bool on_floor_ = true;
  std::uint32_t rng_ = 12345u;
  Vec3f disturbance_Nm_{0.002f, -0.0015f, 0.0005f};
};

}  // namespace fw::selftest
