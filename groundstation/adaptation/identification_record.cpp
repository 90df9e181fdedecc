#include "groundstation/adaptation/identification_record.hpp"

#include <cmath>

namespace gs::adaptation {

std::string_view outcome_name(const estimation::IdentificationResult& result) {
  if (result.refusal == estimation::IdentificationRefusal::none) return "identified";
  return estimation::refusal_name(result.refusal);
}

std::optional<estimation::IdentificationRefusal> parse_identification_outcome(std::string_view name) {
  if (name == "identified") return estimation::IdentificationRefusal::none;
  for (const estimation::IdentificationRefusal refusal : estimation::kAllIdentificationRefusals) {
    if (estimation::refusal_name(refusal) == name) return refusal;
  }
  return std::nullopt;
}

namespace {

// The first figure that is not finite or below its least value, by name, or an empty string.
class FigureCheck {
 public:
  void operator()(const char* name, double value, double least) {
    if (!problem_.empty()) return;
    if (!std::isfinite(value)) {
      problem_ = std::string(name) + " is not finite";
    } else if (value < least) {
      problem_ = std::string(name) + " is negative";
    }
  }
  void operator()(const std::string& problem) {
    if (problem_.empty()) problem_ = problem;
  }
  std::string problem() const { return problem_; }

 private:
  std::string problem_;
};

}  // namespace

std::string validate(const IdentificationRecord& r) {
  FigureCheck check;
  if (!r.vehicle.valid()) check("vehicle " + std::to_string(r.vehicle.node()) + " is not a vehicle's node");
  check("time_s", r.time_s, -INFINITY);
  if (!parse_identification_outcome(outcome_name(r.result))) check("the outcome is not a known refusal");
  const bool refused = r.result.refusal != estimation::IdentificationRefusal::none;
  if (refused && r.result.identified) check("a refused identification carries a fit");
  if (!refused && !r.result.identified) check("an accepted identification carries no fit");
  if (const auto& m = r.result.identified) {
    check("time_constant_s", m->time_constant_s, 0.0);
    check("time_constant_low_s", m->time_constant_low_s, 0.0);
    check("time_constant_high_s", m->time_constant_high_s, 0.0);
    check("inertia_gain", m->inertia_gain, 0.0);
    check("round_trip_s", m->round_trip_s, 0.0);
    check("rms_radps", m->rms_radps, 0.0);
    if (m->samples < 0) check("samples is negative");
    if (m->time_constant_s <= 0.0) check("time_constant_s is not positive");
    if (!(m->time_constant_low_s <= m->time_constant_s && m->time_constant_s <= m->time_constant_high_s))
      check("the 95 % interval does not hold time_constant_s");
  }
  if (r.thrust_gain) {
    check("thrust_gain", *r.thrust_gain, 0.0);
    if (*r.thrust_gain <= 0.0) check("thrust_gain is not positive");
  }
  return check.problem();
}

}  // namespace gs::adaptation
