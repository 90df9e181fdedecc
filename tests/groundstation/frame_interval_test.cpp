// The task laws' time step (groundstation/runtime/frame_interval.hpp): the frames' interval, one
// nominal frame for the first, never negative and at most the configured gap.
#include <catch2/catch.hpp>

#include "groundstation/runtime/frame_interval.hpp"

using gs::runtime::frame_interval_s;
using gs::runtime::FrameIntervalSettings;

TEST_CASE("The first frame counts as one nominal frame") {
  CHECK(frame_interval_s(std::nullopt, 12.0, {}) == 0.005);
  CHECK(frame_interval_s(std::nullopt, 12.0, {0.1, 0.01}) == 0.01);
}

TEST_CASE("Then the interval between arrivals, within [0, max]") {
  const FrameIntervalSettings settings;
  CHECK(frame_interval_s(1.0, 1.005, settings) == Approx(0.005));
  CHECK(frame_interval_s(1.0, 1.04, settings) == Approx(0.04));
  CHECK(frame_interval_s(1.0, 3.0, settings) == 0.05);  // after a gap
  CHECK(frame_interval_s(1.0, 0.99, settings) == 0.0);  // a clock that stepped back
  CHECK(frame_interval_s(1.0, 3.0, {0.2, 0.005}) == 0.2);
}
