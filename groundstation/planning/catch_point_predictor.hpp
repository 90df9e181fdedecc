// The catch-point prediction of Section V: from the current pole estimate (free flight), where
// and when the pole's lower end crosses the catching height on its way down. It runs at every
// motion-capture frame (200 Hz), so it is a fixed-step RK4 integration of eq. (20) with drag;
// inside the step where the lower end passes the height, the crossing is located by a
// safeguarded Newton iteration on the time (first guess: cubic Hermite interpolation of the
// lower end's height), each iterate an RK4 sub-step from the step start, until the height is
// within 1e-7 m. Newton rather than the interpolant alone, because the lower end's height
// p_z - L |n_z| has a kink when the pole passes the horizontal.
//
// A dip of the lower end below the height that starts and ends inside one step is not seen;
// with 50 ms steps that needs a pole turning much faster than any throw.
#pragma once

#include "groundstation/model/pole_free_flight.hpp"

namespace gs::planning {

struct CatchPointPredictorOptions {
  // RK4 step. The integration error grows like (|Omega| dt)^4: with 50 ms the catch point stays
  // within 0.2 mm of a 0.1 ms reference for pole rates up to ~9 rad/s (the throw ends at
  // 2.5 rad/s; catch_point_predictor_test), and a call from the launch costs ~27 RK4 steps
  // (bench_planning).
  double step_s = 0.05;
  double horizon_s = 3.0;  // no crossing within this time: found = false
};

struct CatchPointPrediction {
  bool found = false;
  double t_s = 0.0;  // time from the given state to the crossing
  double x_m = 0.0;  // the lower end's position at the crossing
  double y_m = 0.0;
  model::PoleState state;  // the pole at the crossing
};

// The first instant within the horizon at which the lower end (p_z - L |n_z|) passes downwards
// through catch_height_m. A pole already at or below the height must rise above it first.
CatchPointPrediction predict_catch_point(const model::PoleState& pole, double catch_height_m,
                                         const model::PoleParams& params,
                                         const CatchPointPredictorOptions& options = {});

}  // namespace gs::planning
