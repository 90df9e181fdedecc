// The radio's link budget (groundstation/link/link_budget.hpp): the act's frames counted from the
// protocol's lengths and the configured rates, each signed ground frame with its AUTH, against
// the line's bytes at 10 bits each.
#include <catch2/catch.hpp>

#include "groundstation/link/link_budget.hpp"

using gs::link::GroundLinkConfig;
using gs::link::radio_link_budget;

TEST_CASE("At 115200 baud the act's frames take about half the line each way, and fit") {
  const auto b = radio_link_budget(115200, 200.0, GroundLinkConfig{});
  CHECK(b.line_bytes_per_s == 11520.0);
  // To the vehicle: RATE_THRUST at 200 Hz, GS_HEARTBEAT at 50 and TIMESYNC_REQUEST at 10, each
  // followed by its AUTH; 8-byte frames are 12 bytes framed, TIMESYNC_REQUEST's 5 are 9.
  CHECK(b.to_vehicle.frames_per_s == Approx(2 * (200 + 50 + 10)));
  CHECK(b.to_vehicle.bytes_per_s == Approx(200 * 24 + 50 * 24 + 10 * (9 + 12)));
  // From it: TELEMETRY_RATES 200 Hz, ATTITUDE 100, MOTORS 100, STATUS 10, VEHICLE_HEARTBEAT 50,
  // LINK_SESSION 10, TIMESYNC_REPLY 10, all 8-byte frames, none signed.
  CHECK(b.from_vehicle.frames_per_s == Approx(480));
  CHECK(b.from_vehicle.bytes_per_s == Approx(480 * 12));
  CHECK(b.to_vehicle.utilisation == Approx(6210.0 / 11520.0));
  CHECK(b.fits());
  CHECK(gs::link::describe(b).find("to the vehicle 520 frames/s, 6210 bytes/s, 53.9 %") != std::string::npos);
}

TEST_CASE("A modem too slow for the act is refused; faster heartbeats cost their frames") {
  CHECK_FALSE(radio_link_budget(57600, 200.0, GroundLinkConfig{}).fits());  // 108 % to the vehicle
  CHECK(radio_link_budget(57600, 200.0, GroundLinkConfig{}).to_vehicle.utilisation > 1.0);
  CHECK(radio_link_budget(230400, 200.0, GroundLinkConfig{}).fits());
  GroundLinkConfig busy;
  busy.heartbeat_period_s = 0.01;
  const auto b = radio_link_budget(115200, 200.0, busy);
  CHECK(b.to_vehicle.frames_per_s == Approx(2 * (200 + 100 + 10)));
}
