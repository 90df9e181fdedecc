// The motors' time constant identified from the rate loop's response (issue: fly the vehicles an
// arena has). Real motors lag their commands by 20-60 ms where the airframe file says 30; the
// firmware equalises a known lag to the design's (fw/motor_lag_equaliser.hpp), and this is how
// the ground station comes to know it.
//
// Why the rate loop, and why on the ground. The lag shows in the body rates' response to a rate
// step: the firmware's PI loop on the gyro drives the angular acceleration through the motors, so
// a slower motor rings longer and overshoots more (the damping 1 / (2 sqrt(kp tau)) falls from
// 0.46 at 30 ms to 0.32 at 60 ms). The vehicle's TELEMETRY_RATES carry its gyro at 200 Hz, so
// the ground sees that response cleanly; the motion capture's attitude would show it only
// integrated, in its noise. The collective's lag shows in z only as a delay, inseparable from
// the radio's and the motion capture's. The firmware's loop is the arena's own configuration
// (its gains), so the response is modelled exactly, with three unknowns: the lag tau, the
// inertia's error g = J_file / J_true (the airframe file's inertia is off by up to 20 %),
// and the round trip D (the command's way up plus the telemetry's way down, which the radio's
// jitter blurs).
//
// The fit. The rate commands the ground sent and the rates the vehicle reported over an
// excitation (rate doublets in hover, excitation()) are replayed through the firmware's loop,
// equaliser and a first-order motor for each candidate (tau, g, D); the least squares over roll
// and pitch picks the best, first on a coarse grid, then refined. The confidence is the profile
// of the squared error over tau: the interval where it stays within chi^2_1(95 %) = 3.84 noise
// variances of its minimum. A fit is refused, with the reason, when the telemetry is missing,
// the motors saturated, the vehicle barely moved, the best lag lies at the edge of what a motor
// can be, or the interval is wider than max_interval_fraction of the lag.
//
// Pure: samples and time come in as arguments; the runtime records and asks.
#pragma once

#include <Eigen/Core>
#include <limits>
#include <optional>
#include <string_view>
#include <vector>

namespace gs::estimation {

// The firmware's rate loop on roll and pitch as configured on board (fw::RateControllerConfig,
// fw::AirframeConfig): the ground station's copy of the arena's configuration.
struct RateLoopConfig {
  Eigen::Vector2d kp_per_s{40.0, 40.0};
  Eigen::Vector2d ki_per_s2{40.0, 40.0};
  Eigen::Vector2d integrator_limit_radps2{20.0, 20.0};
  double rate_limit_radps = 10.0;
  double design_time_constant_s = 0.03;  // the airframe's motor lag, which the equaliser keeps
};

struct RateResponseSettings {
  // The excitation: a doublet on roll, then on pitch, of this amplitude and half-period, each
  // followed by a rest (the hover law takes the attitude back).
  double amplitude_radps = 1.5;
  double half_period_s = 0.12;
  double rest_s = 0.4;
  // Search ranges: what a propeller motor's lag, an airframe file's inertia error and a radio's
  // round trip can be.
  double min_time_constant_s = 0.01;
  double max_time_constant_s = 0.1;
  double min_inertia_gain = 0.6;
  double max_inertia_gain = 1.6;
  double max_round_trip_s = 0.1;
  // Refusals: fewer telemetry samples than this fraction of the 200 Hz expected, a peak rate
  // response below this fraction of the amplitude, a 95 % interval wider than this fraction of
  // the lag.
  double min_telemetry_fraction = 0.6;
  double min_response_fraction = 0.3;
  double max_interval_fraction = 0.25;
};

struct MotorIdentification {
  double time_constant_s = 0.0;
  double time_constant_low_s = 0.0;  // the 95 % interval
  double time_constant_high_s = 0.0;
  double inertia_gain =
      1.0;  // J_file / J_true: the airframe file's roll and pitch inertia over the vehicle's
  double round_trip_s = 0.0;
  double rms_radps = 0.0;  // the fit's residual
  int samples = 0;         // telemetry samples fitted
};

enum class IdentificationRefusal : std::uint8_t {
  none,
  no_telemetry,    // too few TELEMETRY_RATES samples over the excitation
  saturated,       // the motors could not follow: the loop was not linear
  no_motion,       // the rates barely answered the excitation
  at_search_edge,  // the best lag is no propeller motor's (or the model does not explain it)
  not_confident,   // the 95 % interval is too wide
};
inline constexpr IdentificationRefusal kAllIdentificationRefusals[] = {
    IdentificationRefusal::no_telemetry, IdentificationRefusal::saturated, IdentificationRefusal::no_motion,
    IdentificationRefusal::at_search_edge, IdentificationRefusal::not_confident};
std::string_view refusal_name(IdentificationRefusal refusal);

struct IdentificationResult {
  IdentificationRefusal refusal = IdentificationRefusal::none;
  std::optional<MotorIdentification> identified;  // set when not refused
};

// What the runtime records while the excitation runs.
struct RateCommandSample {
  double t_s = 0.0;                                      // when sent (the ground's clock)
  Eigen::Vector2d rate_radps = Eigen::Vector2d::Zero();  // roll, pitch as sent
};
struct RateTelemetrySample {
  double t_s = 0.0;                                      // when received (the ground's clock)
  Eigen::Vector2d rate_radps = Eigen::Vector2d::Zero();  // roll, pitch measured on board
  bool saturated = false;                                // the mixer's roll or pitch flag
};

class RateResponseIdentifier {
 public:
  RateResponseIdentifier(const RateLoopConfig& loop, const RateResponseSettings& settings = {});

  // The rates to add to the hover law's command `elapsed_s` after the excitation began (zero
  // before and after it).
  Eigen::Vector2d excitation(double elapsed_s) const;
  double excitation_duration_s() const;

  // Fits the samples recorded from the excitation's start (commands sent and telemetry received
  // from then on, in time order) with the equaliser set to `equalised_time_constant_s` and the
  // rate loop's inertia to `inertia_scale` of the airframe file's, at once (RateResponseFit in one
  // slice). The fit is of the vehicle, whatever is set on board: its inertia gain is J_file / J_true.
  IdentificationResult fit(const std::vector<RateCommandSample>& commands,
                           const std::vector<RateTelemetrySample>& telemetry,
                           double equalised_time_constant_s, double inertia_scale = 1.0) const;

  const RateLoopConfig& loop() const { return loop_; }
  const RateResponseSettings& settings() const { return settings_; }

  // The squared error of one candidate (for tests and the fit's refinement). The replay stops
  // once the sum reaches `stop_at` (it only grows): the value is then at least stop_at, which is
  // all a search that already has a candidate that good needs to know.
  double squared_error(const std::vector<RateCommandSample>& commands,
                       const std::vector<RateTelemetrySample>& telemetry, double equalised_time_constant_s,
                       double time_constant_s, double inertia_gain, double round_trip_s,
                       double inertia_scale = 1.0,
                       double stop_at = std::numeric_limits<double>::infinity()) const;

 private:
  RateLoopConfig loop_;
  RateResponseSettings settings_;
};

// The fit in slices: ~1100 replays of 16 ms CPU in all (bench_runtime), which the runtime spreads
// over its frames, so that no frame waits for the whole (in the HIL guest's emulation the whole
// held the ground station over a second, and the lockstep stepped on without it).
class RateResponseFit {
 public:
  RateResponseFit(const RateResponseIdentifier& identifier, std::vector<RateCommandSample> commands,
                  std::vector<RateTelemetrySample> telemetry, double equalised_time_constant_s,
                  double inertia_scale = 1.0);
  // Runs at most `replays` more replays; true once the result is in.
  bool advance(int replays);
  const std::optional<IdentificationResult>& result() const { return result_; }

 private:
  // Stages 0-3 search the grid ever finer around the best; stage 4 the profile's two sides.
  // A profile point below the best moves the best there, and the profile is taken again (at most
  // kMaxProfileMoves times): its centre was not the minimum, and the curvature there came out
  // negative, an infinite interval (measured: a 52 ms vehicle fitted at 54 ms, refused so).
  static constexpr int kProfileStage = 4;
  static constexpr double kProfileStep_s = 0.001;
  static constexpr int kMaxProfileMoves = 5;
  void queue_grid(const Eigen::Vector3d& around, const Eigen::Vector3d& step, const Eigen::Vector3i& half);
  void queue_profile();
  void finish();

  RateResponseIdentifier identifier_;
  std::vector<RateCommandSample> commands_;
  std::vector<RateTelemetrySample> telemetry_;
  double equalised_s_;
  double inertia_scale_;
  std::vector<Eigen::Vector3d> queue_;  // candidates (tau, g, D) of the stage
  std::size_t next_ = 0;
  int stage_ = 0;
  Eigen::Vector3d best_ = Eigen::Vector3d::Zero();
  double best_error_ = std::numeric_limits<double>::infinity();
  double profile_low_ = std::numeric_limits<double>::infinity();
  double profile_high_ = std::numeric_limits<double>::infinity();
  Eigen::Vector3d profile_best_ = Eigen::Vector3d::Zero();
  double profile_best_error_ = std::numeric_limits<double>::infinity();
  int profile_moves_ = 0;
  std::optional<IdentificationResult> result_;
};

}  // namespace gs::estimation
