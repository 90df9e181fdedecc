#include "groundstation/runtime/attempt_close.hpp"

namespace gs::runtime {

void record_free_flight(std::vector<adaptation::TimedPoleState>& flight, const estimation::PoleEstimate& pole,
                        const AttemptReport& report) {
  if (pole.valid && pole.mode == estimation::PoleMode::free && report.launch_s && !report.impact_s &&
      (flight.empty() || pole.t_s > flight.back().t_s))
    flight.push_back({pole.t_s, pole.state});
}

void close_attempt(const AttemptRequest& request, AttemptReport& report, const AttemptFlight& flight,
                   double now_s, adaptation::Learner& learner) {
  const control::ThrowFrame& frame = flight.frame;
  if (report.launch_s && flight.pole_flight->size() >= 2)
    report.optimal =
        adaptation::evaluate_optimal_catch(*flight.pole_flight, *report.launch_s, flight.pole_model);
  if (report.launch_s && flight.throw_end) {
    // The state tracked last, carried to T along the plan (a few milliseconds of it).
    const planning::ThrowTrajectory& plan = *flight.plan;
    const double T = plan.duration_s();
    const model::PlanarState<double> at_t =
        flight.throw_end->state + plan.state_at(T) - plan.state_at(flight.throw_end->tau_s);
    report.launch_flown = planning::launch_state_of(at_t);
    report.launch_error = adaptation::launch_vector(*report.launch_flown) -
                          adaptation::launch_vector(planning::launch_state_of(plan.state_at(T)));
    if (!flight.target_throw) learner.learn_launch(request.thrower, *report.launch_flown);
  }
  adaptation::ThrowRecord record = record_of(request, report, frame, flight.catch_target_xy_m, now_s);
  // The optimal catch evaluated after the throw counts only if it agrees with the one predicted
  // in flight (adaptation/learner.hpp).
  const bool agrees =
      report.optimal && learner.evaluation_agrees(report.optimal->point, report.predicted_optimal);
  if (flight.target_throw) {
    // A throw to a target is not the Fig. 5 throw whose catch the adaptation learns (its catch
    // point, height and instant are its plan's): its miss is learnt, the record kept, neither
    // adapted nor stored.
    if (agrees) {
      const adaptation::OptimalCatch& o = report.optimal->point;
      const Eigen::Vector3d came_down(o.xy_m.x(), o.xy_m.y(), o.height_m);
      learner.learn_target_miss(frame.to_frame(came_down) -
                                frame.to_frame(flight.target_throw->plan.target_m));
    }
    record.note = "a throw to a target: not adapted";
    learner.keep(record);
  } else {
    if (report.optimal) {
      adaptation::OptimalCatch o = report.optimal->point;
      o.height_m -= frame.origin_m.z();
      o.xy_m = frame.to_frame_xy(o.xy_m);
      learner.learn_optimal_catch(record, o, agrees);
    }
    learner.adapt(record);
  }
}

}  // namespace gs::runtime
