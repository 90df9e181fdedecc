// The pole's half length L learnt from motion capture while the pole rests on a plate.
//
// Every model of the act depends on L: the on-vehicle dynamics (24)-(28), the free flight's
// inertia (20), the impact map (35)-(40). A real pole is cut to within a few millimetres of its
// nominal 1.33 m, and that matters: in a 200-attempt campaign flown on the nominal L (lengths
// drawn within 2 %), 10 of the 13 poles dropped after the catch were in the shortest quarter;
// flown on each pole's true L, 1 of 200 was dropped. Motion capture measures L for free: the
// vehicle's pose gives its plate (the plate's centre lies plate_height above the CG along body
// z) and the pole's pose its centre p and direction n; while the lower end rests on the plate,
// the centre's height over the plate's plane is L (n . z), so
//     L = ((p - plate) . z) / |n . z|.
// Both poses come from the same frame, so the motion capture's latency does not enter. One
// sample has the noise of a few millimetres of position; the mean of a few hundred has a
// fraction of one.
#pragma once

#include <optional>

#include "groundstation/estimation/mocap_pose.hpp"

namespace gs::estimation {

struct PoleLengthParams {
  double nominal_m = 0.665;
  // Samples outside nominal (1 -+ f) are of a pole that is not resting on this plate.
  double plausible_fraction = 0.1;
  // The pole's axis within this angle of the plate's normal: a steeper pole is one the catch
  // has not yet swung up, or one falling, whose end may have left the plate.
  double max_axis_tilt_rad = 0.35;
  // The lower end within this distance of the plate's centre (the plate's radius).
  double max_radial_m = 0.1;
  // Once learnt, a sample farther than this from the mean is a pole leaving the plate (a launch,
  // a bounce) and is not taken.
  double consistency_m = 0.01;
  int samples_to_learn = 50;  // a quarter of a second of motion capture at 200 Hz
  // The mean of at most this many samples, then a moving average over as many: it follows a
  // slow change within consistency_m (an absorber settling). A pole swapped for one more than
  // consistency_m longer or shorter is learnt anew by a new ground-station run.
  int max_samples = 2000;
};

// One sample of L from a vehicle's pose and the pole's, or nullopt when the geometry says the
// pole is not resting upright on this vehicle's plate.
std::optional<double> pole_half_length_sample(const MocapPose& vehicle, const MocapPose& pole,
                                              double plate_height_m, const PoleLengthParams& params);

class PoleLengthLearner {
 public:
  explicit PoleLengthLearner(const PoleLengthParams& params = {}) : params_(params) {}

  // Takes a sample (after pole_half_length_sample); false when it was not taken (implausible, or
  // inconsistent with what was learnt).
  bool add(double sample_m);
  // The learnt L once samples_to_learn samples were taken.
  std::optional<double> learnt() const;
  // The mean of the samples so far, from the first one on: what the filters fly on while L is
  // being learnt. A sample has the motion capture's noise, so even the first is closer than the
  // nominal L of a pole cut a few millimetres off: flown on the nominal L until learnt, the
  // on-vehicle filter put a pole 1.8 % short 12 mm off its poses (NIS about 30), and the mode
  // selector called it free and back six times in the 0.4 s after its placement.
  std::optional<double> estimate() const;
  int samples() const { return count_; }

 private:
  PoleLengthParams params_;
  double mean_m_ = 0.0;
  int count_ = 0;
};

}  // namespace gs::estimation
