// Moving the pole estimate between the modes of the hybrid estimator (Section IV: "this state
// estimate is then fed back to the estimators running in the other modes to correct their
// states"), with the covariance carried through the Jacobian of each map, and the geometry of a
// pole end against a catching plate.
//
//  - free flight -> on vehicle (24): the end that rests on the plate is the lower one (as in the
//    impact map); a = L n_x, b = L n_y for n from that end to the centre, (a', b') from
//    r' = Omega x L n, the offset o from the end's position in the plate frame.
//  - impact: the same after the impact map (35)-(40) (model::impact_map), plus an uncertainty of
//    the post-impact rates (the real impact is neither perfectly inelastic nor instantaneous).
//  - on vehicle -> free flight: (23), (26), (27) (model::free_flight_state_from_pole_on_vehicle), with
//    the plate's position and velocity uncertainty added.
#pragma once

#include <optional>

#include "groundstation/estimation/pole_free_flight_ekf.hpp"
#include "groundstation/estimation/pole_on_vehicle_ekf.hpp"
#include "groundstation/estimation/vehicle_observer.hpp"
#include "pa/constants.hpp"

namespace gs::estimation {

using PoleCovariance = PoleFreeFlightEkf::PoleCovariance;

// Where a pole end may be and still be taken to rest on a plate.
struct PlateContactGate {
  double plate_radius_m = 0.5 * pa::kPlateDiameter_m;
  double radial_margin_m = 0.03;  // beyond the rim (estimate errors, the pole's thickness)
  double height_margin_m = 0.03;  // above or below the plate's plane
  double max_tilt_rad = 1.3;      // of the pole from the inertial vertical
};

// The lower end of a pole (along the inertial z-axis) relative to a plate.
struct PlateContactGeometry {
  double height_m = 0.0;            // above the plate's plane, along its normal
  double radial_m = 0.0;            // from the plate's centre, in its plane
  double approach_speed_mps = 0.0;  // of the end towards the plate (> 0: closing)
  Eigen::Vector3d end_m = Eigen::Vector3d::Zero();
};
PlateContactGeometry plate_contact_geometry(const model::PoleState& pole, const PlateKinematics& plate,
                                            const model::PoleParams& params);

struct OnVehicleSeed {
  PoleOnVehicleEkf::StateVector state = PoleOnVehicleEkf::StateVector::Zero();
  PoleOnVehicleEkf::StateCovariance covariance = PoleOnVehicleEkf::StateCovariance::Identity();
  double direction_sign = 1.0;
};

// The free-flight estimate as an on-vehicle state; nullopt when the lower end is outside the
// gate (the pole cannot be resting on that plate).
std::optional<OnVehicleSeed> on_vehicle_seed_from_free_flight(const model::PoleState& pole,
                                                              const PoleCovariance& covariance,
                                                              const PlateKinematics& plate,
                                                              const model::PoleParams& params,
                                                              const PlateContactGate& gate);

// The on-vehicle state right after the lower end hits a plate (impact map (35)-(40)).
OnVehicleSeed on_vehicle_seed_after_impact(const model::PoleState& before, const PoleCovariance& covariance,
                                           const PlateKinematics& plate, const model::PoleParams& params,
                                           double impact_rate_sigma_mps);

struct FreeFlightSeed {
  model::PoleState state;
  PoleCovariance covariance = PoleCovariance::Identity();
};
FreeFlightSeed free_flight_seed_from_on_vehicle(const PoleOnVehicleEkf& ekf, const PlateKinematics& plate);

}  // namespace gs::estimation
