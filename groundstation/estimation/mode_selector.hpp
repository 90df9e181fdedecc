// Mode selection of the hybrid pole estimator from the innovations (Section IV: "for each
// estimator, the ratio of the innovation to the measurement covariance is computed. Depending on
// these error measures, the most likely mode is chosen").
//
// The paper compares the filters frame by frame and feeds the chosen estimate back to the others.
// A filter re-seeded from the chosen estimate at every frame differs from it by one motion-capture
// period of different dynamics (0.1 mm at 5 ms), far below the noise, so a frame-by-frame
// comparison discriminates slowly (the paper reports launch detection 0.21 s after the nominal
// launch). Here each candidate mode instead accumulates its evidence in a CUSUM (Page's test) on
// the log-likelihood ratio against the active mode:
//   S_c <- max(0, S_c + clamp(l_c - l_active, -cap, cap)),   switch to c when S_c >= threshold.
// While S_c = 0 the candidate is re-seeded from the active estimate after each frame (the
// paper's feedback); while S_c > 0 it runs on its own, so its evidence builds up over as many
// frames as the data support it. The cap keeps one corrupted frame from switching alone. Other
// evidence for a mode (an impact reported by the firmware) lowers its threshold.
//
// Hard physical evidence (the plate's normal force turning negative, the pole's end reaching a
// plate) is handled by the estimator itself (state_estimator.hpp); this class is the statistics.
#pragma once

#include <array>
#include <optional>

#include "groundstation/estimation/pole_mode.hpp"

namespace gs::estimation {

struct ModeSelectorParams {
  double switch_threshold_nats = 12.0;
  double favoured_threshold_nats = 4.0;  // for a mode that other evidence favours
  double max_increment_nats = 7.0;       // per frame, either sign
};

class ModeSelector {
 public:
  explicit ModeSelector(const ModeSelectorParams& params = {});

  void reset(PoleMode active);
  PoleMode active() const { return active_; }

  // One frame's evidence: the log-likelihood of each filter's innovation (nullopt where a filter
  // was not evaluated) and which modes other evidence favours. Returns the new mode on a switch.
  std::optional<PoleMode> step(const std::array<std::optional<double>, kPoleModeCount>& log_likelihood,
                               const std::array<bool, kPoleModeCount>& favoured);

  // S_c of a candidate (0 for the active mode).
  double statistic(PoleMode mode) const { return statistic_[mode_index(mode)]; }
  // True while a candidate accumulates evidence and must not be re-seeded.
  bool accumulating(PoleMode mode) const { return statistic(mode) > 0.0; }
  const ModeSelectorParams& params() const { return params_; }

 private:
  ModeSelectorParams params_;
  PoleMode active_ = PoleMode::free;
  std::array<double, kPoleModeCount> statistic_{};
};

}  // namespace gs::estimation
