// Whether the ground station takes an attempt (Section VII-B), as data: a refusal and its reason
// in words, from what is known of the request, the throw it would fly and the vehicles' motors.
// Pure functions, so that every refusal is tested on its own (attempt_admission_test.cpp); the
// runtime plans a throw to a target (tens of milliseconds) only once the request's own checks
// have passed.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include <Eigen/Core>

#include "groundstation/control/throw_frame.hpp"
#include "groundstation/planning/throw_reach.hpp"
#include "groundstation/planning/throw_trajectory.hpp"
#include "pa/constants.hpp"
#include "pa/vehicle_id.hpp"

namespace gs::runtime {

enum class AttemptRefusal : std::uint8_t {
  none,
  busy,
  not_of_act,
  target_not_planned,
  too_weak,
  outside_volume
};
std::string_view refusal_name(AttemptRefusal refusal);

struct Admission {
  AttemptRefusal refusal = AttemptRefusal::none;
  std::string why;  // in words, with the numbers; empty when admitted
  bool admitted() const { return refusal == AttemptRefusal::none; }
};

// A vehicle's motors as the ground station knows them.
struct VehicleThrust {
  pa::VehicleId vehicle{pa::proto::kGroundNode};
  double gain = 1.0;       // its thrust gain k, measured in flight (estimation/thrust_gain.hpp)
  double battery_V = 0.0;  // the pack's voltage it reports; 0: none reported
};

// See GroundStationConfig::min_thrust_fraction and battery_reference_voltage_V.
struct ThrustAdmission {
  double full_thrust_mps2 =
      4.0 * 3.2 / 0.52;  // a_full, the airframe's (GroundStationConfig::airframe_thrust_max_mps2)
  double min_thrust_fraction = 0.9;
  double battery_reference_voltage_V = 12.6;
  double catch_peak_mps2 = pa::kGravity_mps2 + 4.19;  // g plus the catch manoeuvre's a_max
  double pole_to_vehicle_mass = 0.0;                  // m_p / m_q: the pole's push the thrower carries
};

// Before anything is planned: one attempt at a time, thrown by a vehicle of the act.
Admission admit_request(bool attempt_running, pa::VehicleId thrower);

// The throw the attempt would fly (nullptr: the throw to its target could not be planned)
// against the vehicles' thrust: the thrower's at the throw's peak, the catcher's (if one
// catches) at the catch's.
Admission admit_vehicles(const planning::ThrowTrajectory* flown, const VehicleThrust& thrower,
                         const std::optional<VehicleThrust>& catcher, const ThrustAdmission& settings);

// The arena's volume, from its configuration: a box in arena coordinates that whatever is flown
// stays inside, `margin_m` from its walls, floor and ceiling (a vehicle's arms and propellers, the
// tracking's error).
struct ArenaVolume {
  Eigen::Vector3d min_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d max_m = Eigen::Vector3d::Zero();
  double margin_m = 0.3;
};

// Whether a point (arena coordinates) lies beyond the volume's walls, floor or ceiling (not
// its margin, which is for what is planned).
bool outside_volume(const Eigen::Vector3d& p_m, const ArenaVolume& volume);

// The throw's reach (in `frame`: the thrower's path and the pole's highest point) and the catch
// point (arena coordinates: where the catcher's plate meets the pole) against the volume.
Admission admit_volume(const planning::ThrowReach& reach, const control::ThrowFrame& frame,
                       const Eigen::Vector3d& catch_point_m, const ArenaVolume& volume);

// The highest collective thrust the trajectory needs: its a_q and the pole's push on the plate,
// m_p / m_q of its F_N, which the planar model of eq. (4), (5) leaves out and the vehicle carries
// (the throw's feedback supplies it: 6 % of the thrust at the peak).
double peak_thrust_mps2(const planning::ThrowTrajectory& trajectory, double pole_to_vehicle_mass);

// The vehicle's thrust at full command, k a_full (V / V_ref)^2 (no sag without a reported voltage).
double thrust_ceiling_mps2(const VehicleThrust& vehicle, const ThrustAdmission& settings);

// Which of two vehicles throws when the ground station chooses: the one with the higher thrust
// ceiling, `first` on a tie. A thrower near its ceiling saturates through the throw's last half
// second and launches the pole short and lower (at a ceiling of 0.75 a_full, 4.65 m/s up
// against the plan's 5.5); a weak catcher needs only g plus the catch's a_max. Measured (hil
// campaign --attempts 1000 on the arena envelope, vehicle 1 always throwing): throwers whose thrust
// at their pack's starting voltage was below 0.8 of the airframe's caught 66 of 117, catchers
// below it 85 of 95; with the stronger throwing, 926 of 1000 were caught against 891.
pa::VehicleId stronger_thrower(const VehicleThrust& first, const VehicleThrust& second,
                               const ThrustAdmission& settings);

// When a vehicle's pack is spent for a part (pack_spent).
struct PackSwap {
  // Its thrust ceiling at the voltage it reports below this multiple of the part's peak.
  double margin = 1.15;
  // A vehicle that even on a fresh pack falls short of the margin (a weak airframe, heavy or with
  // worn motors) would swap before every throw for nothing: it swaps once its ceiling has sagged
  // below this fraction of its fresh pack's, k a_full (the corner 10 % heavy at thrust 0.9, whose
  // fresh pack gives 20.1 m/s^2 against the margin's 20.7, swapped 49 times in 50 throws).
  double weak_sag = 0.95;
};

// Whether the vehicle's pack is spent for a part whose peak is `needed_mps2` (PackSwap). False
// without a reported voltage (nothing to judge the pack by).
bool pack_spent(const VehicleThrust& vehicle, double needed_mps2, const PackSwap& swap,
                const ThrustAdmission& settings);

// Empty if the vehicle's thrust ceiling is at least min_thrust_fraction of `needed_mps2`, else
// why not.
std::string thrust_shortfall(const VehicleThrust& vehicle, double needed_mps2, const char* part,
                             const ThrustAdmission& settings);

}  // namespace gs::runtime
