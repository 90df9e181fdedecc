// The truth world's frames (estimation_test_world.hpp) in the estimator's types: kept apart
// from the world, which knows nothing of the estimator.
#pragma once

#include "estimation_test_world.hpp"
#include "groundstation/estimation/state_estimator.hpp"

namespace estimation_test {

inline gs::estimation::MocapPose to_pose(const Pose& p) {
  gs::estimation::MocapPose out;
  out.p_m = p.p;
  out.q = p.q;
  return out;
}

// The frame's three noisy poses.
inline gs::estimation::MocapFrame to_mocap(const Frame& f) {
  gs::estimation::MocapFrame m;
  m.t_s = f.t_s;
  m.vehicle[0] = to_pose(f.vehicle[0]);
  m.vehicle[1] = to_pose(f.vehicle[1]);
  m.pole = to_pose(f.pole);
  return m;
}

// The estimator configured for the world's vehicles. The world's rate loop is a first-order lag
// (WorldParams::rate_tau_s), simpler than a real vehicle's second-order response; the observer's
// second-order model takes it with a second pole far beyond the first: natural frequency
// omega_n = 300 rad/s and the damping that puts the slow pole at -1 / tau (the other lies at
// about -1100 rad/s, within the model's 1 ms integration steps).
inline gs::estimation::VehicleObserverParams observer_for(const WorldParams& world = {}) {
  gs::estimation::VehicleObserverParams p;
  constexpr double kNaturalFrequency_radps = 300.0;
  const double x = 1.0 / (world.rate_tau_s * kNaturalFrequency_radps);
  p.rate_natural_frequency_radps.setConstant(kNaturalFrequency_radps);
  p.rate_damping.setConstant((1.0 + x * x) / (2.0 * x));
  p.thrust_time_constant_s = world.thrust_tau_s;
  return p;
}

inline gs::estimation::StateEstimatorConfig estimator_for(const WorldParams& world = {}) {
  gs::estimation::StateEstimatorConfig c;
  c.vehicle = observer_for(world);
  return c;
}

inline gs::model::VehicleInput to_input(const Command& c) {
  gs::model::VehicleInput in;
  in.a_q_mps2 = c.thrust_mps2;
  in.omega_radps = c.rates_radps;
  return in;
}

}  // namespace estimation_test
