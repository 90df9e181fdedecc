#include "groundstation/link/link_budget.hpp"

#include <cstdio>

#include "pa/constants.hpp"
#include "pa/serial_frame.hpp"

namespace gs::link {
namespace {

using pa::proto::Type;

// A frame of `type` on the line: its payload and the framing's sync, header and CRC.
double framed_bytes(Type type) {
  return static_cast<double>(pa::serial_frame::kMaxBytes - pa::proto::kMaxPayload +
                             pa::proto::find_type(static_cast<std::uint8_t>(type))->length);
}

struct Load {
  double frames_per_s = 0.0;
  double bytes_per_s = 0.0;
  void add(Type type, double rate_hz, bool signed_frame) {
    frames_per_s += rate_hz;
    bytes_per_s += rate_hz * framed_bytes(type);
    if (!signed_frame) return;
    frames_per_s += rate_hz;
    bytes_per_s += rate_hz * framed_bytes(Type::auth);
  }
  StreamLoad on(double line_bytes_per_s) const {
    return {frames_per_s, bytes_per_s, bytes_per_s / line_bytes_per_s};
  }
};

double hz(unsigned period_us) { return 1e6 / period_us; }

}  // namespace

LinkBudget radio_link_budget(unsigned baud, double setpoint_rate_hz, const GroundLinkConfig& ground) {
  LinkBudget budget;
  budget.baud = baud;
  budget.line_bytes_per_s = baud / kBitsPerByte;
  Load down;
  down.add(Type::rate_thrust, setpoint_rate_hz, true);
  down.add(Type::gs_heartbeat, 1.0 / ground.heartbeat_period_s, true);
  down.add(Type::timesync_request, 1.0 / ground.timesync_period_s, true);
  Load up;
  up.add(Type::telemetry_rates, hz(pa::kTelemetryRatesPeriod_us), false);
  up.add(Type::telemetry_attitude, hz(pa::kTelemetryAttitudePeriod_us), false);
  up.add(Type::telemetry_motors, hz(pa::kTelemetryMotorsPeriod_us), false);
  up.add(Type::telemetry_status, hz(pa::kTelemetryStatusPeriod_us), false);
  up.add(Type::vehicle_heartbeat, hz(pa::kVehicleHeartbeatPeriod_us), false);
  up.add(Type::link_session, hz(pa::kLinkSessionPeriod_us), false);
  up.add(Type::timesync_reply, 1.0 / ground.timesync_period_s, false);
  budget.to_vehicle = down.on(budget.line_bytes_per_s);
  budget.from_vehicle = up.on(budget.line_bytes_per_s);
  return budget;
}

std::string describe(const LinkBudget& budget) {
  char line[320];
  std::snprintf(line, sizeof line,
                "radio at %u baud (%.0f bytes/s): to the vehicle %.0f frames/s, %.0f bytes/s, %.1f %%; from "
                "the vehicle %.0f frames/s, %.0f bytes/s, %.1f %% (at most %.0f %% each way)",
                budget.baud, budget.line_bytes_per_s, budget.to_vehicle.frames_per_s,
                budget.to_vehicle.bytes_per_s, 100.0 * budget.to_vehicle.utilisation,
                budget.from_vehicle.frames_per_s, budget.from_vehicle.bytes_per_s,
                100.0 * budget.from_vehicle.utilisation, 100.0 * kMaxRadioUtilisation);
  return line;
}

}  // namespace gs::link
