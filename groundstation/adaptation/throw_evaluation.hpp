// After a throw: the figures a ThrowRecord holds, evaluated from the pole's observed free flight
// (the estimator's pole states from the launch on, e.g. at the 200 Hz motion-capture rate).
//
// - The optimal catching instant (42) "evaluated after each throw" (Section VI-A): the first
//   instant at which the observed flight satisfies (42). Between two samples the residual and the
//   lower end are interpolated linearly (at 200 Hz the lower end falls a few centimetres per
//   sample and (42) is smooth there, so this is within millimetres; tests). A catch ends the
//   observed flight: if it came before (42) was met (the optimal height lay below the height
//   caught at), the flight is continued by the model from the last observed state
//   (planning::find_catching_instant, eq. 20 with drag).
// - The actual catch point: where the observed lower end passed the catching height in use.
// - The pole's energy right after an impact, relative to the contact point (41), for a plate
//   moving or at rest, through the 3D impact map (35)-(40) of model/impact.hpp.
#pragma once

#include <optional>
#include <span>

#include <Eigen/Dense>

#include "groundstation/adaptation/throw_record.hpp"
#include "groundstation/model/pole_free_flight.hpp"
#include "groundstation/planning/catching_instant.hpp"

namespace gs::adaptation {

struct TimedPoleState {
  double t_s = 0.0;  // strictly increasing along a flight
  model::PoleState state;
};

struct OptimalCatchEvaluation {
  OptimalCatch point;         // times relative to launch_t_s
  bool extrapolated = false;  // found by continuing the flight with the model
};

// The first instant of the flight (and, if needed, of its model continuation) satisfying (42).
// launch_t_s is subtracted from the times. Absent if the flight is empty, its times do not
// increase, or (42) is not met within the continuation's horizon.
std::optional<OptimalCatchEvaluation> evaluate_optimal_catch(
    std::span<const TimedPoleState> flight, double launch_t_s, const model::PoleParams& params,
    const planning::CatchingInstantOptions& continuation = {});

// The first downward pass of the observed lower end through height_m (times relative to
// launch_t_s). Absent if the observed flight never passes it.
std::optional<CatchPoint> lower_end_crossing(std::span<const TimedPoleState> flight, double height_m,
                                             double launch_t_s, const model::PoleParams& params);

// The pole's energy relative to the contact point right after it hits a plate moving with
// plate_velocity_mps: m_p g L n_z + (1/2)(m_p L^2 + Theta)|Omega+|^2 (41, in 3D), with Omega+ from
// the impact map and the kinetic part measured relative to the plate.
double post_impact_energy_J(const model::PoleState& before, const Eigen::Vector3d& plate_velocity_mps,
                            const model::PoleParams& params);

}  // namespace gs::adaptation
