// The truth world's frames (estimation_test_world.hpp) in the estimator's types: kept apart
// from the world, which knows nothing of the estimator.
#pragma once

#include "estimation_test_world.hpp"
#include "groundstation/estimation/state_estimator.hpp"

namespace estimation_test {

inline gs::estimation::MocapPose toPose(const Pose& p) {
  gs::estimation::MocapPose out;
  out.p_m = p.p;
  out.q = p.q;
  return out;
}

// The frame's three noisy poses.
inline gs::estimation::MocapFrame toMocap(const Frame& f) {
  gs::estimation::MocapFrame m;
  m.t_s = f.t_s;
  m.vehicle[0] = toPose(f.vehicle[0]);
  m.vehicle[1] = toPose(f.vehicle[1]);
  m.pole = toPose(f.pole);
  return m;
}

inline gs::model::VehicleInput toInput(const Command& c) {
  gs::model::VehicleInput in;
  in.a_q_mps2 = c.thrust_mps2;
  in.omega_radps = c.rates_radps;
  return in;
}

}  // namespace estimation_test
