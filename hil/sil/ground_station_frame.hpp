// A motion-capture frame of the truth plant as the ground station's estimator takes it: the one
// adapter between the two (header-only, so that tests that feed the estimator from the plant use
// it without linking the series). The ground station runs on the motion capture's clock, so the
// frame's time is its capture time; a body the cameras did not see is absent.
#pragma once

#include "groundstation/estimation/state_estimator.hpp"
#include "hil/plant/mocap.hpp"

namespace hil::sil {

inline gs::estimation::MocapFrame to_ground_station_frame(const CapturedFrame& f) {
  gs::estimation::MocapFrame out;
  out.t_s = f.capture_t_s;
  auto pose = [](const CapturedPose& p) {
    gs::estimation::MocapPose q;
    q.p_m = p.position_m;
    q.q = p.attitude;
    return q;
  };
  const auto& v1 = f.pose[static_cast<int>(Body::vehicle1)];
  const auto& v2 = f.pose[static_cast<int>(Body::vehicle2)];
  const auto& pole = f.pose[static_cast<int>(Body::pole)];
  if (v1.seen) out.vehicle[0] = pose(v1);
  if (v2.seen) out.vehicle[1] = pose(v2);
  if (pole.seen) out.pole = pose(pole);
  return out;
}

}  // namespace hil::sil
