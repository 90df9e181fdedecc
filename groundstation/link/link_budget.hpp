// Whether the act's frames fit a vehicle's serial radio (a transparent modem on a UART, framed
// with pa/serial_frame.hpp): frames and bytes a second each way at the configured rates, and the
// share of the line they take. Every ground frame a vehicle acts on is followed by its AUTH
// (docs/security.md), so the setpoints cost twice their frames. Rare frames (commands and their
// acknowledgements, impacts) are not counted: the headroom below kMaxRadioUtilisation is theirs.
// Pure (link_budget_test.cpp).
#pragma once

#include <string>

#include "groundstation/link/ground_link.hpp"

namespace gs::link {

// A line's bytes cost 10 bits each: start, 8 data, stop (8N1).
inline constexpr double kBitsPerByte = 10.0;
// A radio whose busier direction is above this share of its line is refused: commands and their
// retries, acknowledgements and impacts come on top, and a full modem buffer is latency.
inline constexpr double kMaxRadioUtilisation = 0.8;

struct StreamLoad {
  double frames_per_s = 0.0;
  double bytes_per_s = 0.0;
  double utilisation = 0.0;  // of the line's bytes a second
};

struct LinkBudget {
  unsigned baud = 0;
  double line_bytes_per_s = 0.0;
  StreamLoad to_vehicle;    // setpoints, heartbeats, TIMESYNC requests, each with its AUTH
  StreamLoad from_vehicle;  // telemetry, heartbeats, LINK_SESSION, TIMESYNC replies
  bool fits() const {
    return to_vehicle.utilisation <= kMaxRadioUtilisation && from_vehicle.utilisation <= kMaxRadioUtilisation;
  }
};

// One vehicle's radio at `baud`, with setpoints at `setpoint_rate_hz` (one per motion-capture
// frame), the ground link's heartbeat and TIMESYNC periods and the vehicle's default periods
// (pa/constants.hpp).
LinkBudget radio_link_budget(unsigned baud, double setpoint_rate_hz, const GroundLinkConfig& ground);

// The budget for the operator, one line each way:
// "radio at 115200 baud (11520 bytes/s): to the vehicle 520 frames/s, 6210 bytes/s, 53.9 %; ..."
std::string describe(const LinkBudget& budget);

}  // namespace gs::link
