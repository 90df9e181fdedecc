#include "groundstation/adaptation/throw_record.hpp"

#include <cmath>

namespace gs::adaptation {

std::string_view to_string(ThrowOutcome outcome) {
  switch (outcome) {
    case ThrowOutcome::caught: return "caught";
    case ThrowOutcome::dropped: return "dropped";
    case ThrowOutcome::missed: return "missed";
    case ThrowOutcome::offset_practice: return "offset_practice";
    case ThrowOutcome::aborted_out_of_reach: return "aborted_out_of_reach";
    case ThrowOutcome::aborted: return "aborted";
    case ThrowOutcome::throw_only: return "throw_only";
  }
  return "unknown";
}

std::optional<ThrowOutcome> parse_throw_outcome(std::string_view name) {
  for (const ThrowOutcome outcome : kAllThrowOutcomes) {
    if (to_string(outcome) == name) return outcome;
  }
  return std::nullopt;
}

bool catcher_flew_to_target(ThrowOutcome outcome) {
  switch (outcome) {
    case ThrowOutcome::caught:
    case ThrowOutcome::dropped:
    case ThrowOutcome::missed:
    case ThrowOutcome::offset_practice: return true;
    case ThrowOutcome::aborted_out_of_reach:
    case ThrowOutcome::aborted:
    case ThrowOutcome::throw_only: return false;
  }
  return false;
}

namespace {

// The first non-finite field, by name, or an empty string.
class FiniteCheck {
 public:
  void operator()(const char* name, double value) {
    if (problem_.empty() && !std::isfinite(value)) problem_ = std::string(name) + " is not finite";
  }
  void operator()(const char* name, const Eigen::Vector2d& value) {
    (*this)((std::string(name) + ".x").c_str(), value.x());
    (*this)((std::string(name) + ".y").c_str(), value.y());
  }
  std::string problem() const { return problem_; }

 private:
  std::string problem_;
};

}  // namespace

std::string validate(const ThrowRecord& r) {
  if (!parse_throw_outcome(to_string(r.outcome))) return "outcome is not one of the known outcomes";
  FiniteCheck check;
  check("time_s", r.time_s);
  check("launch.x_m", r.launch.x_m);
  check("launch_y_m", r.launch_y_m);
  check("launch.z_m", r.launch.z_m);
  check("launch.vx_mps", r.launch.vx_mps);
  check("launch_vy_mps", r.launch_vy_mps);
  check("launch.vz_mps", r.launch.vz_mps);
  check("launch.alpha_rad", r.launch.alpha_rad);
  check("launch.alpha_dot_radps", r.launch.alpha_dot_radps);
  check("catch_height_used_m", r.catch_height_used_m);
  check("waiting_xy_m", r.waiting_xy_m);
  if (r.target_xy_m) check("target_xy_m", *r.target_xy_m);
  if (r.predicted) {
    check("predicted.xy_m", r.predicted->xy_m);
    check("predicted.t_s", r.predicted->t_s);
  }
  if (r.actual) {
    check("actual.xy_m", r.actual->xy_m);
    check("actual.t_s", r.actual->t_s);
  }
  if (r.optimal) {
    check("optimal.t_s", r.optimal->t_s);
    check("optimal.height_m", r.optimal->height_m);
    check("optimal.xy_m", r.optimal->xy_m);
  }
  if (r.catcher_at_impact_xy_m) check("catcher_at_impact_xy_m", *r.catcher_at_impact_xy_m);
  if (r.energy_after_impact_J) check("energy_after_impact_J", *r.energy_after_impact_J);
  return check.problem();
}

std::optional<Eigen::Vector2d> offset_bias_sample(const ThrowRecord& record) {
  if (!catcher_flew_to_target(record.outcome)) return std::nullopt;
  if (!record.catcher_at_impact_xy_m || !record.target_xy_m) return std::nullopt;
  return Eigen::Vector2d(*record.catcher_at_impact_xy_m - *record.target_xy_m);
}

}  // namespace gs::adaptation
