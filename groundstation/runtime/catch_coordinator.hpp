// The catch of one attempt (Section V): when the catcher's z manoeuvre starts so that it comes
// to rest at the catching height at the expected catching instant, this throw's own optimal
// catching instant (42) predicted shortly after the launch (the retiming), the catch manoeuvre
// re-planned at every frame from the latest catch-point prediction, and the verdicts the
// sequencer acts on (out of reach, infeasible, missed). State and time are passed in; it flies
// nothing itself (the runtime tracks catch_trajectory()).
#pragma once

#include <optional>

#include <Eigen/Core>

#include "groundstation/adaptation/adaptation_law.hpp"
#include "groundstation/control/throw_frame.hpp"
#include "groundstation/estimation/state_estimator.hpp"
#include "groundstation/mission/vehicle_sequencer.hpp"
#include "groundstation/planning/catch_trajectory.hpp"
#include "groundstation/planning/height_shift.hpp"
#include "groundstation/runtime/attempt.hpp"

namespace gs::runtime {

struct CatchSettings {
  double t_xy_s = 0.65;
  double xy_lead_s = 0.5;
  double a_max_mps2 = 4.19;
  double k_max_mps3 = 18.0;
  double reach_m = 1.0;          // a predicted catch point farther from the waiting point aborts
  double verdict_delay_s = 0.1;  // after the launch, before reach and feasibility are judged
  double retime_s = 0.4;         // this throw's (42) moves the catch's end height this long after the launch
  double retime_max_m = 1.0;
  // Upwards it may move farther and faster: a shift up accelerates up while the catcher dives
  // (thrust 5.6 + 9 of 20 m/s^2) and down while it brakes (14 - 9, above the 1 m/s^2 minimum), so
  // it lightens the braking instead of adding to it. A thrower with 55-60 ms motors sends the pole
  // to (42) 0.64 m above the learnt height on average (20-25 ms: 0.04), up to 1.6 m with a
  // drag-light pole; the catch 0.4 m below (42) dropped it (+0.04 to +0.08 J). Envelope campaigns
  // (hil campaign --attempts 1000 --plant hil/config/envelope.yaml), seed 1: 966 -> 971 caught,
  // seed 2: 971 -> 977; the built-in plant 1000 of 1000 either way.
  double retime_up_max_m = 1.5;
  double missed_margin_m = 0.15;  // the lower end this far below the catching height, free: missed
  // No catch lower than this, whatever (42) and the learning say: a slowly turning pole (strong
  // rotational drag, a weak thrower) meets (42) a metre or more below the usual height, and the
  // learnt height followed it down to 1.0 m, where the catcher then met the floor
  // (hil fly --throws 50 --plant hil/config/envelope/half_extremes.yaml).
  double min_height_m = 2.0;
  // The retimed height is reached by a shift of the z reference (planning::HeightShift) whose
  // acceleration stays within this: the dive's deceleration already asks g + a_max = 14 m/s^2 of
  // a thrust limited to 20 (5: 256 of the 300 attempts above, 8: 259).
  double shift_max_accel_mps2 = 6.0;
  double shift_up_max_accel_mps2 = 9.0;
  // The search for this throw's (42) at every frame of the retiming: twice the planner's RK4
  // step (planning::CatchingInstantOptions), and a horizon beyond any flight the act throws.
  double retime_step_s = 0.01;
  double retime_horizon_s = 2.0;
};

// `height_m` raised to the settings' floor.
double floored_catch_height_m(double height_m, const CatchSettings& settings);

// What the catch sees of the world at a frame.
struct CatchView {
  mission::Task catcher_task = mission::Task::parked;
  estimation::PoleEstimate pole;
  model::PoleParams pole_model;
  Eigen::Vector3d catcher_position_m = Eigen::Vector3d::Zero();
  control::ThrowFrame frame;               // the attempt's throw frame
  adaptation::AdaptationState adaptation;  // its offset bias compensates the prediction
  Eigen::Vector2d catch_offset_m = Eigen::Vector2d::Zero();
};

class CatchCoordinator {
 public:
  // `limits`: the catcher's inputs, which the feasibility verdict checks the manoeuvre against.
  CatchCoordinator(const CatchSettings& settings, const planning::InputLimits& limits)
      : settings_(settings), limits_(limits) {}

  // A new attempt: no manoeuvre, no verdicts.
  void reset();
  // The throw has started: the catch from `report.waiting_xy_m` at `report.catch_height_m` (the
  // adapted values), due when the z manoeuvre must start for it to end `catch_instant_s` after
  // the launch expected at `launch_s`.
  void plan(const AttemptReport& report, double launch_s, double catch_instant_s);
  // Before the verdicts: this throw's optimal catch (42), moving the catch's end height (in
  // `report`, reached by height_shift()) within bounds for retime_s after the launch. The shift
  // ends with the manoeuvre, or at (42)'s instant when that is later.
  void retime(double now_s, const CatchView& view, AttemptReport& report);
  // At every frame from the throw's start: the catch point predicted, the manoeuvre re-planned,
  // the verdicts judged once the prediction has converged; the report's prediction and travel.
  void update(double now_s, const CatchView& view, AttemptReport& report);
  // The catcher starts the manoeuvre now (no later than planned). Returns how long the impact
  // may take from now: the manoeuvre's remaining time plus `margin_s`, for a z manoeuvre ending
  // at `catch_height_m`.
  double start(double now_s, double catch_height_m, double margin_s);

  bool due(double now_s) const { return now_s >= start_s_; }
  bool unreachable() const { return unreachable_; }
  bool infeasible() const { return infeasible_; }
  bool missed() const { return missed_; }
  double start_s() const { return start_s_; }
  const Eigen::Vector2d& target_xy_m() const { return target_xy_m_; }
  const std::optional<planning::CatchTrajectory>& trajectory() const { return trajectory_; }
  // Added to the trajectory's z: the way from the adapted height to the retimed one.
  const planning::HeightShift& height_shift() const { return shift_; }
  // The z manoeuvre of a catch ending with the plate at `catch_height_m`.
  planning::MinimaxZManoeuvre z_manoeuvre(double catch_height_m) const;

 private:
  CatchSettings settings_;
  planning::InputLimits limits_;
  std::optional<planning::CatchTrajectory> trajectory_;
  planning::HeightShift shift_;
  double start_s_ = 0.0;
  double adapted_height_m_ = 0.0;
  Eigen::Vector2d target_xy_m_ = Eigen::Vector2d::Zero();
  bool unreachable_ = false;
  bool infeasible_ = false;
  bool missed_ = false;
  Eigen::Vector3d last_catcher_m_ = Eigen::Vector3d::Zero();
};

}  // namespace gs::runtime
