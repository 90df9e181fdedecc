// The crash policy (firmware/core/include/fw/crash_policy.hpp) over every mode: a crash stops the
// motors on the floor; in the air, under the ground's control or on board, only when the vehicle
// tumbles.
#include <catch2/catch.hpp>

#include "fw/crash_policy.hpp"
#include "pa/protocol.hpp"

using pa::proto::Mode;

TEST_CASE("A crash stops the motors on the floor, and in the air only a tumbling vehicle's") {
  for (std::uint8_t m = 0; m <= pa::proto::kModeMax; ++m) {
    const Mode mode = static_cast<Mode>(m);
    CAPTURE(pa::proto::mode_name(mode));
    const bool airborne = mode == Mode::flying || mode == Mode::hold || mode == Mode::failsafe_hover ||
                          mode == Mode::failsafe_descent;
    CHECK(fw::crash_stops_motors(mode, 1.0f, 0.5f) == !airborne);
    CHECK(fw::crash_stops_motors(mode, 0.51f, 0.5f) == !airborne);
    CHECK(fw::crash_stops_motors(mode, 0.5f, 0.5f));  // tumbling: always
    CHECK(fw::crash_stops_motors(mode, -1.0f, 0.5f));
  }
}
