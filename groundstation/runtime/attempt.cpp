#include "groundstation/runtime/attempt.hpp"

namespace gs::runtime {

void note_task_entry(const AttemptRequest& request, bool running, AttemptReport& report,
                     pa::VehicleId vehicle, mission::Task task, mission::Reason reason, double now_s,
                     const Eigen::Vector3d& here_m) {
  using mission::Reason;
  using mission::Task;
  if (task == Task::rebalance && !report.impact_s) {
    report.impact_s = now_s;
    report.catcher_at_impact_m = here_m;
  }
  if (running && vehicle == request.thrower && task == Task::release && report.thrower_end == Reason::none)
    report.thrower_end = reason;
  if (request.catch_it && vehicle != request.thrower &&
      (task == Task::clear || task == Task::rebalance || (task == Task::hover && report.catch_start_s)) &&
      report.catcher_end == Reason::none)
    report.catcher_end = reason;
}

adaptation::ThrowOutcome outcome_of(const AttemptRequest& request, const AttemptReport& report) {
  using adaptation::ThrowOutcome;
  using mission::Reason;
  if (!request.catch_it) return ThrowOutcome::throw_only;
  if (report.caught) return ThrowOutcome::caught;
  switch (report.catcher_end) {
    case Reason::out_of_reach: return ThrowOutcome::aborted_out_of_reach;
    case Reason::infeasible:
    case Reason::abort_requested:
    case Reason::vehicle_lost:
    case Reason::estimate_lost: return ThrowOutcome::aborted;
    default: break;
  }
  if (request.catch_offset_m.norm() > 0.0) return ThrowOutcome::offset_practice;
  return report.impact_s ? ThrowOutcome::dropped : ThrowOutcome::missed;
}

adaptation::ThrowRecord record_of(const AttemptRequest& request, const AttemptReport& report,
                                  const control::ThrowFrame& frame, const Eigen::Vector2d& catch_target_xy_m,
                                  double now_s) {
  adaptation::ThrowRecord record;
  record.time_s = report.launch_s.value_or(now_s);
  if (report.launch_flown) record.launch = *report.launch_flown;
  record.outcome = outcome_of(request, report);
  record.thrower = request.thrower;
  record.catch_height_used_m = report.catch_height_m - frame.origin_m.z();
  record.waiting_xy_m = frame.to_frame_xy(report.waiting_xy_m);
  if (report.catch_start_s) record.target_xy_m = frame.to_frame_xy(catch_target_xy_m);
  record.energy_after_impact_J = report.energy_after_impact_J;
  if (report.impact_s && report.catcher_at_impact_m && adaptation::catcher_flew_to_target(record.outcome))
    record.catcher_at_impact_xy_m = frame.to_frame_xy(report.catcher_at_impact_m->head<2>());
  return record;
}

}  // namespace gs::runtime
