// What the ground station learns from one attempt to the next, and keeps: the adaptation of the
// catch (Section VI: catching height, waiting point, offset bias), the mean optimal catching
// instant, the throw learnt from past trials (throw_learning.hpp) and the mean miss of throws
// to targets. It gates what it is given (an evaluation that disagrees with its in-flight
// prediction, an odd throw far from all others), writes the durable store
// (adaptation_store.hpp) and, at construction, replays the store's history so that a restart
// continues where the last run stopped. Time-free: the runtime hands it each attempt's results.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "groundstation/adaptation/adaptation_law.hpp"
#include "groundstation/adaptation/adaptation_store.hpp"
#include "groundstation/adaptation/throw_evaluation.hpp"
#include "groundstation/adaptation/throw_learning.hpp"
#include "pa/vehicle_id.hpp"

namespace gs::adaptation {

// Each vehicle of the act learns its own throw: in passes both throw, and one correction learnt
// from both throwers' errors swung with a period of about ten passes and grew until a catch was
// missed (hil fly --passes 100: 83 caught on the built-in plant, 46 on full batteries; with one
// correction each, 100 and 76).
using ThrowCorrections = std::array<ThrowCorrection, pa::kActVehicles.size()>;

// What the learner has learnt, carried from one run to the next without a store.
struct Learnt {
  AdaptationState state;
  double catch_instant_s = 0.8;  // after the launch
  int catch_instant_samples = 0;
  ThrowCorrections throw_corrections;  // each vehicle's throw learnt from its past trials
};

struct LearnerSettings {
  // A throw's optimal catch point, evaluated after it, further than these from the one predicted
  // in flight is rejected (evaluation_agrees).
  double gate_m = 0.2;
  double gate_s = 0.1;
  // A sample further than this from the adapted values counts only as the outlier_repeats-th
  // such throw in a row.
  double outlier_m = 0.5;
  int outlier_repeats = 3;
  ThrowLearningSettings throw_learning;  // gain 0: the throw is not learnt
};

class Learner {
 public:
  // Starts from `learnt` when given, else from the nominal values (`settings_of_pole`, the
  // nominal catching instant); a store (non-empty path) overrides both: its adapted values and
  // the means over its current epoch. Throws StoreError when the store cannot be opened.
  Learner(const LearnerSettings& settings, const AdaptationSettings& adaptation,
          double nominal_catch_instant_s, const planning::PlanarLaunchState& planned_launch,
          const LaunchMatrix& inverse_sensitivity, const std::optional<Learnt>& learnt,
          const std::string& store_path);

  const AdaptationState& state() const { return state_; }
  const AdaptationSettings& adaptation_settings() const { return adaptation_; }
  double catch_instant_s() const { return catch_instant_s_; }
  // `thrower`'s learnt throw (a vehicle of the act).
  const ThrowCorrection& throw_correction(pa::VehicleId thrower) const {
    return throw_corrections_[pa::act_slot(thrower)];
  }
  // Where throws to targets came down from where they were aimed, on average, in the throw's
  // frame (along, across, up).
  const Eigen::Vector3d& target_miss_m() const { return target_miss_m_; }
  Learnt learnt() const { return {state_, catch_instant_s_, catch_instant_samples_, throw_corrections_}; }

  // The evaluation of (42) on the observed flight agrees with the prediction of it made in
  // flight (both in the same frame).
  bool evaluation_agrees(const OptimalCatch& evaluated, const std::optional<OptimalCatch>& predicted) const;

  // A Fig. 5 throw's flown launch state: `thrower`'s next throw's correction.
  void learn_launch(pa::VehicleId thrower, const planning::PlanarLaunchState& flown);
  // A Fig. 5 throw's optimal catch (its frame), gated: taken into the catching instant's mean
  // and the record's `optimal` when `agrees` and not an odd throw, else a note in the record.
  void learn_optimal_catch(ThrowRecord& record, const OptimalCatch& evaluated, bool agrees);
  // A throw to a target's miss (its frame), unless an outlier.
  void learn_target_miss(const Eigen::Vector3d& miss_m);
  // Adapts to a valid record (Section VI) and stores it (one transaction: the throw and the
  // values that include it); keeps it in records(), as it keeps an invalid one.
  void adapt(const ThrowRecord& record);
  // Keeps a record that is not adapted to (a throw to a target) in records().
  void keep(const ThrowRecord& record) { records_.push_back(record); }
  // Every record given, oldest first.
  const std::vector<ThrowRecord>& records() const { return records_; }

 private:
  LearnerSettings settings_;
  AdaptationSettings adaptation_;
  planning::PlanarLaunchState planned_launch_;
  LaunchMatrix inverse_sensitivity_;
  AdaptationState state_;
  std::optional<AdaptationStore> store_;
  std::vector<ThrowRecord> records_;
  double catch_instant_s_;
  int catch_instant_samples_ = 0;
  ThrowCorrections throw_corrections_;
  int odd_throws_ = 0;  // consecutive throws far from the adapted values
  Eigen::Vector3d target_miss_m_ = Eigen::Vector3d::Zero();
  int target_miss_samples_ = 0;
};

}  // namespace gs::adaptation
