// The identification flight of a take-off: the doublets added to the commands from its start, the
// samples recorded only while it lasts, and the fit's result only once its slices are done.
#include <catch2/catch.hpp>

#include "groundstation/runtime/identification_flight.hpp"

using gs::estimation::IdentificationRefusal;
using gs::runtime::IdentificationFlight;

TEST_CASE("nothing before the start; the doublets from it") {
  IdentificationFlight flight;
  CHECK_FALSE(flight.running());
  CHECK(flight.excitation(1.0).isZero());
  CHECK_FALSE(flight.finish(100.0));
  flight.start(10.0, 0.03);
  CHECK(flight.running());
  CHECK(flight.excitation(9.9).isZero());
  CHECK(flight.excitation(10.05)[0] > 0.0);
  CHECK(flight.excitation(10.05)[1] == 0.0);
}

TEST_CASE("a flight whose vehicle sent no rates ends refused, and the next take-off starts afresh") {
  IdentificationFlight flight;
  flight.start(0.0, 0.03);
  for (double t = 0.0; t < 1.0; t += 0.01) flight.command_sent(t, flight.excitation(t));
  CHECK_FALSE(flight.finish(1.0));  // the excitation still runs
  const auto result = flight.finish(2.0);
  REQUIRE(result);
  CHECK(result->refusal == IdentificationRefusal::no_telemetry);
  CHECK_FALSE(flight.running());
  CHECK_FALSE(flight.finish(3.0));
  flight.start(5.0, 0.03);
  CHECK(flight.running());
}

TEST_CASE("a TELEMETRY_RATES counts as saturated when roll or pitch was not fully allocated") {
  for (std::uint8_t bits : {0x1, 0x2, 0x3, 0x4, 0x8, 0x0}) {
    CAPTURE(int{bits});
    IdentificationFlight flight;
    flight.start(0.0, 0.03);
    for (double t = 0.0; t < 1.6; t += 0.005) {
      flight.command_sent(t, flight.excitation(t));
      flight.telemetry(t, pa::proto::TelemetryRates{{0.0f, 0.0f, 0.0f}, 9.81f, bits});
    }
    std::optional<gs::estimation::IdentificationResult> result;
    for (int i = 0; i < 100 && !result; ++i) result = flight.finish(2.0);
    REQUIRE(result);
    // Not saturated, rates that never moved are no motion.
    CHECK(result->refusal ==
          ((bits & 3u) ? IdentificationRefusal::saturated : IdentificationRefusal::no_motion));
  }
}
