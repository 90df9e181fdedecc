#include "groundstation/estimation/estimator_health.hpp"

#include <cmath>

namespace gs::estimation {
namespace {

constexpr double kIntervalWeight = 0.05;  // ~20 samples: 0.1 s at 200 Hz
constexpr double kNisWeight = 0.01;       // ~100 samples

}  // namespace

void BodyHealthTracker::sample(double t_s) {
  if (samples_ > 0) {
    const double dt = t_s - last_t_s_;
    if (dt > 0.0) {
      interval_s_ = interval_s_ > 0.0 ? interval_s_ + kIntervalWeight * (dt - interval_s_) : dt;
    }
  }
  last_t_s_ = t_s;
  ++samples_;
}

void BodyHealthTracker::innovation(double nis) {
  if (!std::isfinite(nis)) return;
  last_nis_ = nis;
  mean_nis_ = nis_samples_ == 0 ? nis : mean_nis_ + kNisWeight * (nis - mean_nis_);
  ++nis_samples_;
  if (nis > nis_gate_) ++exceedances_;
}

BodyHealth snapshot(const BodyHealthTracker& tracker, double t_now_s) {
  BodyHealth h;
  h.seen = tracker.seen();
  h.samples = tracker.samples();
  h.rejected = tracker.rejected_samples();
  h.rate_Hz = tracker.rate_Hz();
  h.age_s = tracker.age_s(t_now_s);
  h.last_nis = tracker.last_nis();
  h.mean_nis = tracker.mean_nis();
  h.nis_exceedances = tracker.nis_exceedances();
  return h;
}

}  // namespace gs::estimation
