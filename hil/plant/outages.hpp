// Losses that come in bursts: outages of a fixed length at exponentially distributed gaps,
// covering a given fraction of the time on average. A radio fades and a marker is hidden for a
// while rather than frame by frame; independent losses of the same rate are far easier on a
// controller (one missed setpoint is never noticed, 100 ms without any are).
#pragma once

#include <cmath>

namespace hil {

class OutageSchedule {
 public:
  // `fraction` of the time (0..1) in outages of `length_s` each (> 0).
  OutageSchedule(double fraction, double length_s) : fraction_(fraction), length_s_(length_s) {}

  // Whether t_s falls in an outage. Times must not go back; `uniform01` draws from [0, 1) (a
  // gap per outage passed, so the schedule is reproducible from the caller's generator).
  template <class Uniform>
  bool out(double t_s, Uniform&& uniform01) {
    if (fraction_ <= 0.0) return false;
    if (fraction_ >= 1.0) return true;
    const double mean_gap_s = length_s_ * (1.0 - fraction_) / fraction_;
    while (t_s >= end_s_) {
      start_s_ = end_s_ - mean_gap_s * std::log(1.0 - uniform01());
      end_s_ = start_s_ + length_s_;
    }
    return t_s >= start_s_;
  }

 private:
  double fraction_;
  double length_s_;
  double start_s_ = 0.0;
  double end_s_ = 0.0;
};

}  // namespace hil
