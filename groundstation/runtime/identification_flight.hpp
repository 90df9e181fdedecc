// The identification each take-off flies (estimation/rate_response.hpp): rate doublets on roll and
// pitch once the vehicle is airborne, the commands it sent and the rates it reported recorded
// meanwhile, then the fit. A step of every take-off rather than a separate `identify` run: a
// battery swap or a new propeller changes the motors, and the doublets cost 1.3 s of the climb to
// the throw's origin, where the vehicle waits for the pole anyway.
#pragma once

#include <optional>
#include <vector>

#include "groundstation/estimation/rate_response.hpp"
#include "pa/protocol.hpp"

namespace gs::runtime {

class IdentificationFlight {
 public:
  IdentificationFlight()
      : IdentificationFlight(estimation::RateResponseIdentifier{estimation::RateLoopConfig{}}) {}
  explicit IdentificationFlight(const estimation::RateResponseIdentifier& identifier)
      : designed_(identifier), identifier_(identifier) {}

  // Starts the excitation at `now_s` with the firmware's equaliser set to `equalised_s` and its
  // rate loop's inertia to `inertia_scale` of the airframe file's, its doublets `amplitude_scale`
  // times the designed amplitude.
  void start(double now_s, double equalised_s, double inertia_scale = 1.0, double amplitude_scale = 1.0);
  bool running() const { return start_s_.has_value(); }
  // Ends a flight before its fit: no excitation from now, nothing recorded, no result.
  void stop();

  // The roll and pitch rates to add to the command sent at `now_s`.
  Eigen::Vector2d excitation(double now_s) const;
  void command_sent(double now_s, const Eigen::Vector2d& rate_radps);
  void telemetry(double now_s, const Eigen::Vector2d& rate_radps, bool saturated);
  // A TELEMETRY_RATES as received: roll and pitch, saturated when either was not fully allocated.
  void telemetry(double now_s, const pa::proto::TelemetryRates& rates);

  // Once the excitation and the responses' way back are over, the fit, kReplaysPerCall replays a
  // call (the runtime's tick), so that no frame waits for it: its result when in, and the flight
  // ends.
  std::optional<estimation::IdentificationResult> finish(double now_s);
  // ~0.3 ms a tick here (bench_runtime BM_MotorLagFit: 16 ms for ~1100 replays), the fit done in
  // ~55 ticks.
  static constexpr int kReplaysPerCall = 20;

 private:
  bool recording(double now_s) const;  // from the start to the fit
  // The last responses arrive a round trip after the excitation; the fit waits this long.
  static constexpr double kSettle_s = 0.3;
  // What one flight keeps of each (a flight records ~260 of each at the radio's 200 Hz): a vehicle
  // flooding its telemetry costs no memory beyond it.
  static constexpr std::size_t kMaxSamples = 1024;
  estimation::RateResponseIdentifier designed_;    // at the designed amplitude
  estimation::RateResponseIdentifier identifier_;  // this flight's
  std::optional<double> start_s_;
  double equalised_s_ = 0.0;
  double inertia_scale_ = 1.0;
  std::vector<estimation::RateCommandSample> commands_;
  std::vector<estimation::RateTelemetrySample> telemetry_;
  std::optional<estimation::RateResponseFit> fit_;
};

}  // namespace gs::runtime
