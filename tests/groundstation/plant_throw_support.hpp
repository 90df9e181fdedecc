// What the tests that fly the optimal throw on the HIL truth plant share (throw_on_plant_test,
// throw_through_firmware_test): the plan's origin in the arena and the start, the ground
// station's states read off the plant's truth, the motion-capture frame as the estimator takes
// it, and the check of the catch point predictions against the true crossing.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include "groundstation/control/balancing_lqr.hpp"
#include "groundstation/estimation/state_estimator.hpp"
#include "groundstation/model/planar_pole_vehicle.hpp"
#include "groundstation/planning/catch_point_predictor.hpp"
#include "hil/plant/plant.hpp"
#include "hil/sil/ground_station_frame.hpp"

namespace plant_throw {

// The plan's origin (hover) in the arena: the throw dips 0.95 m below it.
inline const hil::Vec3 kStart_m(0.0, 0.0, 1.5);

// The throw's plane faces yaw_rad (a target throw, target_throw.hpp; 0 for +x): the helpers
// below read the truth in the frame turned by it, where the plan's planar model holds.
inline hil::Mat3 to_throw_frame(double yaw_rad) {
  return Eigen::AngleAxisd(-yaw_rad, hil::Vec3::UnitZ()).toRotationMatrix();
}

// The throw's start on the plant: vehicle 1 hovering with the plate at the plan's origin, facing
// the throw's plane and carrying the pole's weight, the pole upright and still on the plate,
// vehicle 2 parked aside.
inline void place_for_throw(hil::Plant& plant, double yaw_rad = 0.0) {
  const hil::PlantConfig& config = plant.config();
  hil::VehicleState thrower =
      plant.hovering_vehicle(kStart_m - hil::Vec3(0, 0, config.vehicle.plate_height_m), yaw_rad);
  for (double& f : thrower.motor_thrust_N) f += config.pole.mass_kg * config.gravity_mps2 / 4.0;
  plant.set_vehicle(pa::kVehicle1, thrower);
  plant.set_vehicle(pa::kVehicle2, plant.parked_vehicle(-2.0, 2.0, 0.0));
  const double L = config.pole.half_length_m;
  plant.set_pole(hil::Plant::make_pole(plant.plate_centre_m(pa::kVehicle1) + L * hil::Vec3::UnitZ(),
                                       hil::Vec3::UnitZ(), hil::Vec3::Zero(), hil::Vec3::Zero()));
}

// The pivot (the plate's centre, where the pole's lower end rests) of the plant's vehicle 1,
// relative to the plan's origin, and its velocity.
struct Pivot {
  hil::Vec3 p_m;
  hil::Vec3 v_mps;
};
inline Pivot pivot_of(const hil::Plant& plant, double yaw_rad = 0.0) {
  const hil::VehicleState& v = plant.vehicle(pa::kVehicle1);
  const hil::Vec3 lever = plant.plate_centre_m(pa::kVehicle1) - v.body.position_m;
  const hil::Mat3 turn = to_throw_frame(yaw_rad);
  return {turn * (plant.plate_centre_m(pa::kVehicle1) - kStart_m),
          turn * (v.body.velocity_mps + v.body.rate_inertial_radps().cross(lever))};
}

// The planar state (planar_pole_vehicle.hpp) of the plant's vehicle 1 and pole, from the truth:
// the pivot is the plate's centre (where the pole's lower end rests), theta the pitch of the
// thrust axis, alpha the pole's tilt from the vertical towards +x.
inline gs::model::PlanarState<double> planar_state(const hil::Plant& plant, double yaw_rad = 0.0) {
  const hil::Mat3 turn = to_throw_frame(yaw_rad);
  const hil::Mat3 r = turn * plant.vehicle(pa::kVehicle1).body.rotation();
  const Pivot pivot = pivot_of(plant, yaw_rad);
  const hil::Vec3 n = turn * plant.pole().axis();
  gs::model::PlanarState<double> s;
  s << pivot.p_m.x(), pivot.p_m.z(), pivot.v_mps.x(), pivot.v_mps.z(), std::atan2(r(0, 2), r(2, 2)),
      std::atan2(n.x(), n.z()), (turn * plant.pole().body.rate_inertial_radps()).y();
  return s;
}

// s_qp of eq. (31) from the truth, relative to the plan's origin, for the balancing LQR: the
// pivot (plate centre) and its velocity, Z-Y-X Euler angles of eq. (3) (the thrust axis is
// (cos phi sin theta, -sin phi, cos phi cos theta) at psi = 0), and the pole's deflection
// L n = (a, b, c) (eq. (24)) with its rate L (omega x n).
inline Eigen::VectorXd balancing_state(const hil::Plant& plant, double half_length_m, double yaw_rad = 0.0) {
  namespace bal = gs::control::balancing;
  const hil::Mat3 turn = to_throw_frame(yaw_rad);
  const hil::Mat3 r = turn * plant.vehicle(pa::kVehicle1).body.rotation();
  const Pivot pivot = pivot_of(plant, yaw_rad);
  const hil::Vec3 n = turn * plant.pole().axis();
  const hil::Vec3 n_dot = (turn * plant.pole().body.rate_inertial_radps()).cross(n);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(bal::kStateSize);
  x.segment<3>(bal::kX) = pivot.p_m;
  x.segment<3>(bal::kVx) = pivot.v_mps;
  x(bal::kRoll) = std::asin(std::clamp(-r(1, 2), -1.0, 1.0));
  x(bal::kPitch) = std::atan2(r(0, 2), r(2, 2));
  x(bal::kYaw) = std::atan2(r(1, 0), r(0, 0));
  x(bal::kA) = half_length_m * n.x();
  x(bal::kB) = half_length_m * n.y();
  x(bal::kADot) = half_length_m * n_dot.x();
  x(bal::kBDot) = half_length_m * n_dot.y();
  return x;
}

// The motion-capture frame as the estimator takes it (the arena's own adapter).
inline gs::estimation::MocapFrame to_estimator_frame(const hil::CapturedFrame& f) {
  return hil::sil::to_ground_station_frame(f);
}

// Where the plant's pole really comes down through the catching height, against the catch
// points the ground station predicted on the way.
class CatchCheck {
 public:
  explicit CatchCheck(double catch_height_m) : height_m_(catch_height_m) {}
  double height_m() const { return height_m_; }

  // After each plant step at time t_s: the first downward crossing of the pole's lower end,
  // once the pole has been launched.
  void watch(const hil::Plant& plant, double t_s, bool launched) {
    const hil::PoleConfig& pole = plant.config().pole;
    const hil::Vec3 a = hil::pole_end_m(plant.pole(), pole, 0), b = hil::pole_end_m(plant.pole(), pole, 1);
    const hil::Vec3 low = a.z() < b.z() ? a : b;
    if (launched && std::isnan(crossing_t_s_) && previous_low_z_m_ > height_m_ && low.z() <= height_m_) {
      crossing_t_s_ = t_s;
      crossing_m_ = low;
    }
    previous_low_z_m_ = low.z();
  }
  void predicted(double t_s, const gs::planning::CatchPointPrediction& p) {
    predictions_.emplace_back(t_s, p);
  }

  std::optional<double> crossing_t_s() const {
    return std::isnan(crossing_t_s_) ? std::nullopt : std::optional<double>(crossing_t_s_);
  }
  const hil::Vec3& crossing_m() const { return crossing_m_; }  // valid once crossing_t_s() is set
  // The figures both plant-throw tests bound: the miss of the prediction 0.1 s after the release
  // and 0.15 s before the crossing. Empty when the pole never came down through the height.
  struct Errors {
    double crossing_t_s;
    double after_release_m;
    double before_crossing_m;
  };
  std::optional<Errors> errors(double release_t_s) const {
    if (std::isnan(crossing_t_s_)) return std::nullopt;
    return Errors{crossing_t_s_, error_at(release_t_s + 0.1), error_at(crossing_t_s_ - 0.15)};
  }
  // The horizontal miss of the first prediction made at or after t_s from `point` (by default the
  // true crossing; 1e9 when there is none or it found no crossing).
  double error_at(double t_s) const { return error_at(t_s, crossing_m_); }
  double error_at(double t_s, const hil::Vec3& point_m) const {
    for (const auto& [tp, p] : predictions_) {
      if (tp < t_s - 1e-9) continue;
      return p.found ? std::hypot(p.x_m - point_m.x(), p.y_m - point_m.y()) : 1e9;
    }
    return 1e9;
  }

 private:
  double height_m_;
  double previous_low_z_m_ = std::numeric_limits<double>::quiet_NaN();  // NaN before the first step
  // NaN until the crossing (GCC 12 at -O3 warns falsely on an optional's payload here).
  double crossing_t_s_ = std::numeric_limits<double>::quiet_NaN();
  hil::Vec3 crossing_m_ = hil::Vec3::Zero();
  std::vector<std::pair<double, gs::planning::CatchPointPrediction>> predictions_;
};

}  // namespace plant_throw
