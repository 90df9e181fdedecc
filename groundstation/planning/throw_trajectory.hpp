// A planned throw (problem (34)) as the Hermite-Simpson collocation points it was solved on,
// with the interpolants the transcription implies: between two knots the state is the cubic
// Hermite polynomial through the knot states and their derivatives f(s, u), and the input is the
// quadratic through knot, midpoint and knot (the throw planner makes it linear: the midpoint input
// is the mean of the knots').
#pragma once

#include <vector>

#include "groundstation/model/planar_pole_vehicle.hpp"

namespace gs::planning {

struct ThrowTrajectory {
  // In time order: even indices are the knots t_k (k = 0..N, not necessarily evenly spaced), odd
  // indices the interval midpoints; 2N + 1 entries in each vector.
  std::vector<double> t_s;
  std::vector<model::PlanarState<double>> state;
  std::vector<model::PlanarInput<double>> input;
  std::vector<double> normal_force_per_mass_mps2;  // F_N / m_p at each point
  model::PlanarPoleVehicleParams params;

  int intervals() const { return static_cast<int>(t_s.size() / 2); }
  double duration_s() const { return t_s.empty() ? 0.0 : t_s.back(); }

  // The interpolants; t is clamped into [0, T]. Precondition: at least one interval.
  model::PlanarState<double> state_at(double t_s) const;
  model::PlanarInput<double> input_at(double t_s) const;
};

}  // namespace gs::planning
