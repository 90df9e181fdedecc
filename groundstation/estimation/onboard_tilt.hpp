// How far a vehicle's own attitude estimate has tilted from motion capture's, and when to tell it.
//
// In flight the firmware integrates its gyro alone (fw/attitude_estimator.hpp: a multirotor's
// accelerometer reads the thrust's direction, not gravity), so its "up" drifts: measured, 4.5
// degrees after five minutes and 30 throws and catches. The vehicle flies on it only when motion
// capture is out of reach (a hold, a failsafe) or in a landing's last centimetres, and there a
// lean is flown as a drift: that vehicle, landing, flew 30 m sideways and 15 m up. The ground
// station sees both attitudes: each on-board attitude report is compared with its own estimate of
// the vehicle, the true up is taken into the on-board inertial frame (yaw-free: the on-board
// heading is its own), averaged while the vehicle turns slowly (the two attitudes are some
// milliseconds apart), and sent back (COMMAND correct_tilt) once the mean is off by more than
// motion capture's noise. Pure: time and attitudes are passed in (onboard_tilt_test.cpp).
#pragma once

#include <cstdint>
#include <optional>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace gs::estimation {

struct OnboardTiltSettings {
  double window_s = 1.0;         // each mean's span
  int min_reports = 50;          // calm reports in it (they come every 10 ms)
  double calm_rate_radps = 0.5;  // faster turns make the two attitudes' few ms apart count
  double correct_above_rad = 0.005;
  double settle_s = 0.3;  // after a correction, until the reports show it
};

class OnboardTilt {
 public:
  explicit OnboardTilt(const OnboardTiltSettings& settings = {}) : settings_(settings) {}

  // One on-board attitude report at t_s (body to the vehicle's own inertial frame), the vehicle's
  // attitude as motion capture estimates it (body to arena) and its body rates' magnitude. A
  // correction is due when a window's mean is off: the true up's x and y in the on-board frame
  // (tilt_correction_argument bounds them as the protocol does); the window starts anew either way.
  std::optional<Eigen::Vector2d> report(double t_s, const Eigen::Quaterniond& onboard,
                                        const Eigen::Quaterniond& measured, double rate_radps);
  // The last window's mean tilt, rad (for telemetry and tests).
  double last_error_rad() const { return last_error_rad_; }

  // The true up in the on-board inertial frame: up in the body as measured, turned by the
  // on-board attitude.
  static Eigen::Vector3d true_up_onboard(const Eigen::Quaterniond& onboard,
                                         const Eigen::Quaterniond& measured);

 private:
  OnboardTiltSettings settings_;
  std::optional<double> window_start_s_;
  double blocked_until_s_ = -1e9;
  Eigen::Vector2d sum_ = Eigen::Vector2d::Zero();
  int count_ = 0;
  double last_error_rad_ = 0.0;
};

// COMMAND correct_tilt's argument (pa/protocol.hpp) for a correction report() gave, each axis
// clamped to the protocol's kTiltMaxCounts (the firmware refuses more).
std::int32_t tilt_correction_argument(const Eigen::Vector2d& true_up_xy);

}  // namespace gs::estimation
