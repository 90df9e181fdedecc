// Health of the estimator, ready to publish as telemetry: per motion-capture body the sample
// rate, the age of the last sample and the innovation statistics, and the pole's mode.
#pragma once

#include <cstdint>

#include "groundstation/estimation/pole_mode.hpp"

namespace gs::estimation {

// Running statistics of one motion-capture body.
class BodyHealthTracker {
 public:
  // nis_gate: the NIS above which a sample counts as an exceedance (the 99 % chi-square point
  // for the body's measurement dimension).
  explicit BodyHealthTracker(double nis_gate = 15.09) : nis_gate_(nis_gate) {}

  void sample(double t_s);          // a sample arrived (used or not)
  void rejected() { ++rejected_; }  // unusable or an outlier
  void innovation(double nis);

  bool seen() const { return samples_ > 0; }
  std::uint64_t samples() const { return samples_; }
  std::uint64_t rejected_samples() const { return rejected_; }
  double rate_Hz() const { return interval_s_ > 0.0 ? 1.0 / interval_s_ : 0.0; }
  double age_s(double t_now_s) const { return samples_ > 0 ? t_now_s - last_t_s_ : -1.0; }
  double last_nis() const { return last_nis_; }
  double mean_nis() const { return mean_nis_; }  // exponentially weighted, ~100 samples
  std::uint64_t nis_exceedances() const { return exceedances_; }
  double nis_gate() const { return nis_gate_; }

 private:
  double nis_gate_;
  std::uint64_t samples_ = 0;
  std::uint64_t rejected_ = 0;
  std::uint64_t nis_samples_ = 0;
  std::uint64_t exceedances_ = 0;
  double last_t_s_ = 0.0;
  double interval_s_ = 0.0;  // exponentially weighted mean of the sample intervals
  double last_nis_ = 0.0;
  double mean_nis_ = 0.0;
};

struct BodyHealth {
  bool seen = false;
  std::uint64_t samples = 0;
  std::uint64_t rejected = 0;
  double rate_Hz = 0.0;
  double age_s = -1.0;  // -1 before the first sample
  double last_nis = 0.0;
  double mean_nis = 0.0;
  std::uint64_t nis_exceedances = 0;
};

BodyHealth snapshot(const BodyHealthTracker& tracker, double t_now_s);

struct EstimatorHealth {
  double t_s = 0.0;
  BodyHealth vehicle[2];
  BodyHealth pole;
  PoleMode mode = PoleMode::free;
  double time_in_mode_s = 0.0;
  std::uint64_t mode_switches = 0;
  std::uint64_t frames = 0;
  std::uint64_t frames_out_of_order = 0;  // older than the estimator's time: ignored
  double pole_position_sigma_m = 0.0;     // sqrt of the mean position variance of the estimate
  double drag_scale = 1.0;
};

}  // namespace gs::estimation
