// The throw flown with a correction of its end state (the learnt throw,
// adaptation/throw_learning.hpp): the TV-LQR tracks the plan shifted by a correction c of the
// launch state (x, z, x', z', alpha, alpha' at T), blended in over the throw (zero at its start,
// where the plan starts from hover, and c at T),
//     s_ref(tau) = s_planned(tau) + sigma(tau / T) c,   sigma(u) = 3u^2 - 2u^3,
// and G, the sensitivity of the flown end state to c: the tracking loop follows a shifted
// reference only in part, and a shift of one component moves others. G comes from the closed
// loop linearised along the plan,
//     ds' = (A - B K) ds + B K sigma c,   G c = ds(T),
// with the TV-LQR's K. It depends on the plan and its gains alone, so a shared Fig. 5 throw
// carries it (throw_book.hpp): a campaign integrates it once, not once per attempt.
#pragma once

#include <Eigen/Core>

#include "groundstation/model/planar_pole_vehicle.hpp"
#include "groundstation/planning/throw_tracking.hpp"

namespace gs::planning {

using EndShift = Eigen::Matrix<double, 6, 1>;             // c, in launch-state order
using EndShiftSensitivity = Eigen::Matrix<double, 6, 6>;  // G

// sigma(tau / T) c as a planar state (tau clamped to [0, T]; the vehicle's pitch theta unshifted).
model::PlanarState<double> reference_shift(const EndShift& end_shift, double tau_s, double duration_s);

// G for the tracker's plan and gains, integrating the linearised closed loop (RK4) in steps of
// step_s.
EndShiftSensitivity end_shift_sensitivity(const ThrowTracker& tracker, double step_s = 0.001);

}  // namespace gs::planning
