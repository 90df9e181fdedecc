#include "groundstation/adaptation/learner.hpp"

#include <cmath>

namespace gs::adaptation {

Learner::Learner(const LearnerSettings& settings, const AdaptationSettings& adaptation,
                 double nominal_catch_instant_s, const planning::PlanarLaunchState& planned_launch,
                 const LaunchMatrix& inverse_sensitivity, const std::optional<Learnt>& learnt,
                 const std::string& store_path)
    : settings_(settings),
      adaptation_(adaptation),
      planned_launch_(planned_launch),
      inverse_sensitivity_(inverse_sensitivity),
      state_(initial_adaptation(adaptation)),
      catch_instant_s_(nominal_catch_instant_s) {
  if (learnt) {
    state_ = learnt->state;
    catch_instant_s_ = learnt->catch_instant_s;
    catch_instant_samples_ = learnt->catch_instant_samples;
    throw_corrections_ = learnt->throw_corrections;
  }
  if (store_path.empty()) return;
  store_.emplace(AdaptationStore::open_or_create(store_path, adaptation_));
  const AdaptationSnapshot snapshot = store_->adaptation();
  state_ = snapshot.state;
  catch_instant_samples_ = 0;
  for (const StoredThrow& t : store_->history()) {
    if (t.id < snapshot.epoch_first_id) continue;
    // The throw's correction is the sum of the epoch's launch errors (throw_learning.hpp); a
    // throw without a launch keeps the zero state (no vehicle launches from the origin at rest).
    if (launch_vector(t.record.launch) != LaunchVector::Zero())
      learn_launch(t.record.thrower.value_or(pa::kVehicle1), t.record.launch);
    if (!t.record.optimal) continue;
    ++catch_instant_samples_;
    catch_instant_s_ += (t.record.optimal->t_s - catch_instant_s_) / catch_instant_samples_;
  }
}

// A sample that disagrees with its in-flight prediction is an evaluation gone wrong (a flight
// cut short, an extrapolation from a bad estimate), not a throw, and a mean would carry it for
// ever (measured: one sample of -6.4 m moved the catching height by 0.9 m and every later catch
// missed). Gating against the adapted mean instead locks a bad first sample in (measured: the
// following good ones were 0.5 m away and rejected).
bool Learner::evaluation_agrees(const OptimalCatch& o, const std::optional<OptimalCatch>& predicted) const {
  if (!predicted) return false;
  const OptimalCatch& p = *predicted;
  return std::abs(o.height_m - p.height_m) < settings_.gate_m &&
         (o.xy_m - p.xy_m).norm() < settings_.gate_m && std::abs(o.t_s - p.t_s) < settings_.gate_s;
}

void Learner::learn_launch(pa::VehicleId thrower, const planning::PlanarLaunchState& flown) {
  if (settings_.throw_learning.gain <= 0.0 || !pa::is_act_vehicle(thrower)) return;
  ThrowCorrection& correction = throw_corrections_[pa::act_slot(thrower)];
  correction =
      learn_from_throw(correction, flown, planned_launch_, settings_.throw_learning, inverse_sensitivity_);
}

// A sound evaluation of a throw far from all the others (the thrower pushed aside, a gust) is
// one odd throw, not the new mean: with few samples it would move the waiting point out of reach
// of the next catch (measured: a throw pushed 1.5 m sideways made the next catch infeasible). It
// counts once such throws repeat (the system has changed), so that a bad first sample cannot
// lock the mean either.
void Learner::learn_optimal_catch(ThrowRecord& record, const OptimalCatch& o, bool agrees) {
  bool plausible = agrees;
  if (plausible && state_.catch_point_samples > 0) {
    const bool odd = std::abs(o.height_m - state_.catch_height_m) > settings_.outlier_m ||
                     (o.xy_m - state_.waiting_xy_m).norm() > settings_.outlier_m;
    odd_throws_ = odd ? odd_throws_ + 1 : 0;
    if (odd && odd_throws_ < settings_.outlier_repeats) plausible = false;
  }
  if (plausible) {
    record.optimal = o;
    catch_instant_samples_ += 1;
    catch_instant_s_ += (o.t_s - catch_instant_s_) / static_cast<double>(catch_instant_samples_);
  } else {
    record.note = "optimal catch evaluation rejected: outside the adaptation gate";
  }
}

void Learner::learn_target_miss(const Eigen::Vector3d& miss_m) {
  if (miss_m.norm() > settings_.outlier_m) return;
  ++target_miss_samples_;
  target_miss_m_ +=
      iterative_mean_gain(target_miss_samples_ - 1, adaptation_.window) * (miss_m - target_miss_m_);
}

void Learner::adapt(const ThrowRecord& record) {
  if (validate(record).empty()) {
    if (store_) {
      store_->record(record);
      state_ = store_->adaptation().state;
    } else {
      state_ = adaptation::adapt(state_, record, adaptation_.window);
    }
  }
  records_.push_back(record);
}

}  // namespace gs::adaptation
