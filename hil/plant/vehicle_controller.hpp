// A position and attitude controller for the scenario runner: it flies a plant vehicle from
// the plant's TRUE state, so that recorded scenarios have vehicles that hover, hold a catch
// point or balance a pole. It is a test-data generator, not part of the flight stack: the real
// vehicles are flown by the firmware's rate loop and the ground station's controllers.
//
// Position: a PD law (with an integral on height, which takes up a pole's weight or a thrust
// mismatch) gives a desired acceleration; the thrust vector m (a + g e_z) sets the desired body
// z-axis (tilt limited) and the collective thrust; a geometric attitude law (the error of
// R_d^T R, as in Lee, Leok and McClamroch 2010) gives body torques; the X layout of motor.hpp
// is inverted for the four motor thrusts, which are clipped to the motors' range. The motor lag
// is partly cancelled with the motors' true thrust, so the attitude loop can be fast enough for
// balancing.
#pragma once

#include <Eigen/Dense>

#include "hil/plant/plant_config.hpp"
#include "hil/plant/types.hpp"

namespace hil {

struct VehicleControllerGains {
  double position_radps = 2.5;  // natural frequency of the horizontal position loop
  double height_radps = 3.0;    // ... and of the height loop
  double position_damping = 0.9;
  double height_integral_per_s = 1.0;  // integral rate relative to the height loop's stiffness
  double attitude_radps = 25.0;        // natural frequency of the attitude loop
  double attitude_damping = 0.8;
  // The motors are driven so that their thrust approaches the demand with this time constant
  // instead of their own lag (the command overshoots the demand by the lag ratio, from the
  // motors' TRUE thrust); 0 leaves the lag as it is.
  double motor_response_s = 0.01;
  double tilt_max_rad = 0.6;
  // track_rates(): the body-rate loop's bandwidth (the firmware's rate loop, fw/rate_controller.hpp,
  // is a proportional law of this kind), yaw at a third of it.
  double rate_radps = 40.0;
  double acceleration_max_mps2 = 8.0;  // horizontal acceleration demand limit
};

struct VehicleSetpoint {
  Vec3 position_m = Vec3::Zero();
  Vec3 velocity_mps = Vec3::Zero();
  Vec3 acceleration_mps2 = Vec3::Zero();  // feedforward
  double yaw_rad = 0.0;
  // false: the horizontal position and velocity terms are off and the horizontal acceleration is
  // the feedforward alone (a pole balancer supplies it); the height is still held.
  bool hold_horizontal = true;
};

class VehicleController {
 public:
  // `vehicle` gives the nominal mass, inertia, geometry and motor range the controller assumes
  // (the plant may differ: motor gains, drag).
  VehicleController(const VehicleConfig& vehicle, double gravity_mps2,
                    const VehicleControllerGains& gains = {});

  MotorCommands update(const VehicleState& truth, const VehicleSetpoint& setpoint, double dt_s);
  // The paper's vehicle inputs (eq. (1), (2)): the mass-normalised collective thrust and the
  // body rates, as the ground station commands them and the on-board rate loop flies them
  // (a stand-in for the firmware's loop: proportional on the body-rate error, gyroscopic terms
  // cancelled, the motor lag shortened as in update()).
  MotorCommands track_rates(const VehicleState& truth, double thrust_mps2,
                            const Vec3& rates_body_radps) const;
  void reset() { height_integral_m_s_ = 0.0; }

 private:
  // Motor commands that produce the wrench (collective thrust N; body torques N m).
  MotorCommands motors(const VehicleState& truth, const Eigen::Vector4d& wrench) const;

  VehicleConfig vehicle_;
  double gravity_mps2_;
  VehicleControllerGains gains_;
  Eigen::Matrix4d allocation_inverse_;  // [thrust; torque] -> motor thrusts
  double height_integral_m_s_ = 0.0;
};

}  // namespace hil
