// The time step the task laws integrate over (the carrot's travel, the position integral, the
// take-off ramp; task_control.hpp): the interval between two motion-capture frames as they
// arrived on the ground clock. Pure (frame_interval_test.cpp).
#pragma once

#include <optional>

namespace gs::runtime {

struct FrameIntervalSettings {
  // After a gap in the stream (motion capture lost, a plant paused) one frame integrates at most
  // this much, so the integral and the carrot do not jump by a whole gap's worth: ten frames at
  // the motion capture's 200 Hz.
  double max_s = 0.05;
  // The first frame has no predecessor: it counts as one nominal 200 Hz frame.
  double first_s = 0.005;
};

// From the previous frame's arrival `last_s` (none before the first) to `now_s`, within
// [0, max_s]: a clock that steps back gives 0, not a negative step.
double frame_interval_s(std::optional<double> last_s, double now_s, const FrameIntervalSettings& settings);

}  // namespace gs::runtime
