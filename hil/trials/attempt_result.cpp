#include "hil/trials/attempt_result.hpp"

#include "pa/vehicle_id.hpp"

namespace hil::trials {

const Schema<AttemptResult>& attempt_schema() {
  using R = AttemptResult;
  static const Schema<R> schema{
      field("throw", &R::throw_number),
      named_field("outcome", &R::outcome, gs::adaptation::to_string, gs::adaptation::parse_throw_outcome),
      field("flight_s", &R::flight_s, "%.4f"),
      field("catch_height_m", &R::catch_height_m, "%.4f"),
      field("catch_x_m", &R::catch_x_m, "%.4f"),
      field("catch_y_m", &R::catch_y_m, "%.4f"),
      field("travel_m", &R::travel_m, "%.4f"),
      field("energy_error_J", &R::energy_error_J, "%.5f"),
      field("abort_reason", &R::abort_reason),
      field("planned_height_m", &R::planned_height_m, "%.4f"),
      field("optimal_height_m", &R::optimal_height_m, "%.4f"),
      field("impact", &R::impact),
      field("vehicle_crashed", &R::vehicle_crashed),
      field("predicted_target_miss_m", &R::predicted_target_miss_m, "%.4f"),
      field("target_miss_m", &R::target_miss_m, "%.4f"),
      field("thrower", &R::thrower),
      field("innovation_switches", &R::innovation_switches),
  };
  return schema;
}

Schema<AttemptResult> fly_throws_columns() {
  return columns(attempt_schema(),
                 {"throw", "outcome", "flight_s", "catch_height_m", "catch_x_m", "catch_y_m", "travel_m",
                  "energy_error_J", "abort_reason", "planned_height_m", "optimal_height_m"});
}

std::string encode_result(const AttemptResult& r) { return encode(attempt_schema(), r); }

// A line that decodes but that no attempt could have written (a thrower outside the act, a
// negative count: a shard's file damaged or edited) is refused as one that does not decode.
bool decode_result(const std::string& line, AttemptResult& r) {
  return decode(attempt_schema(), line, r) &&
         (r.thrower == pa::kVehicle1.node() || r.thrower == pa::kVehicle2.node()) &&
         r.innovation_switches >= 0;
}

}  // namespace hil::trials
