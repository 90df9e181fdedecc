// The radio between the ground CAN bus and a vehicle's CAN bus, as the simulation sees it: a
// CAN bridge that delays every frame by a latency plus random jitter and loses a fraction of
// them, in each direction independently. A radio link delivers in order, so a frame never
// overtakes the one before it. Deterministic for a given seed; time is passed in.
#pragma once

#include <cstdint>
#include <deque>
#include <random>

#include "hil/plant/outages.hpp"
#include "pa/protocol.hpp"

namespace hil {

struct RadioConfig {
  double latency_s = 0.008;  // one way; a motion-capture arena's radio is a few ms
  double jitter_s = 0.002;   // uniform in [0, jitter_s] on top of the latency
  double loss = 0.0;         // probability that a frame is lost, 0..1
  std::uint32_t seed = 1;
  // > 0: the losses come as outages of this length (both directions at once), `loss` the
  // fraction of the time the radio is out (hil/plant/outages.hpp); 0: each frame independently.
  double outage_s = 0.0;
};

enum class Side { ground, vehicle };

class RadioBridge {
 public:
  // Throws std::invalid_argument for a configuration outside its ranges.
  explicit RadioBridge(const RadioConfig& config);

  // A frame read from `from`'s bus at time t_s, to be carried to the other side.
  void offer(Side from, const pa::proto::Frame& frame, double t_s);
  // The next frame due on `to`'s bus by now_s, oldest first.
  bool deliver(Side to, double now_s, pa::proto::Frame& out);

  // Whether frames offered from now on may be lost (by default they may; the arena follows
  // Plant::losses_active()).
  void set_losses_active(bool active) { losses_active_ = active; }

  std::uint64_t offered(Side from) const { return dir(from).offered; }
  std::uint64_t lost(Side from) const { return dir(from).lost; }

 private:
  struct InFlight {
    double due_s;
    pa::proto::Frame frame;
  };
  struct Direction {
    std::deque<InFlight> queue;
    double last_due_s = -1e300;
    std::uint64_t offered = 0;
    std::uint64_t lost = 0;
  };
  Direction& dir(Side from) { return from == Side::ground ? uplink_ : downlink_; }
  const Direction& dir(Side from) const { return from == Side::ground ? uplink_ : downlink_; }

  RadioConfig config_;
  std::mt19937 rng_;
  std::uniform_real_distribution<double> unit_{0.0, 1.0};
  OutageSchedule outages_;
  bool losses_active_ = true;
  Direction uplink_;    // ground -> vehicle
  Direction downlink_;  // vehicle -> ground
};

}  // namespace hil
