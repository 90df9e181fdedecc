// The referee's account of one attempt (series.hpp judges it on the plant's truth) and its schema
// (record_schema.hpp): the one list of its fields that the workers' reports (every field, exact)
// and the CSV files (throws.csv of `hil fly` and `hil campaign`) are written from.
#pragma once

#include <string>

#include "groundstation/adaptation/throw_record.hpp"
#include "hil/trials/record_schema.hpp"

namespace hil::trials {

// The columns of throws.csv are its fields' CSV names (docs/report.md).
struct AttemptResult {
  int throw_number = 0;
  int thrower = 1;  // the throwing vehicle's node
  // caught, dropped, missed, aborted (abort_reason says why), offset_practice or throw_only
  gs::adaptation::ThrowOutcome outcome = gs::adaptation::ThrowOutcome::aborted;
  double flight_s = -1.0;        // launch to impact (or to the catch height's crossing)
  double catch_height_m = -1.0;  // lower end at the impact, arena frame
  double catch_x_m = 0.0, catch_y_m = 0.0;
  double travel_m = 0.0;        // from the catcher's waiting point to the catch point (series.cpp)
  double energy_error_J = 0.0;  // E - E* right after the impact (0 without one)
  bool impact = false;
  std::string abort_reason;        // the ground station's, for an aborted catch
  double planned_height_m = -1.0;  // the ground station's catching height for the throw (-1: none)
  // This throw's optimal catching height (42) as the ground station predicted it in flight, which
  // the planned height follows within CatchSettings' bounds (-1: none).
  double optimal_height_m = -1.0;
  bool vehicle_crashed = false;  // a vehicle touched the floor at speed or was killed
  // A throw to a target: how far from it (horizontally) the ground station's converged
  // catch-point prediction and the true impact were (-1: none).
  double predicted_target_miss_m = -1.0;
  double target_miss_m = -1.0;
  // The ground station's pole mode switches on the innovations during the attempt (its
  // estimator's health, not the referee's judgement): a balanced pole called free and back.
  int innovation_switches = 0;
};

// Every field of AttemptResult, in the order of throws.csv's columns and then the rest.
const Schema<AttemptResult>& attempt_schema();

// The columns of throws.csv as `hil fly` writes it (the campaign's are in campaign.hpp).
Schema<AttemptResult> fly_throws_columns();

// One attempt's result as one line and back (the workers' reports; tab-separated, no newline,
// every field of attempt_schema()). decode_result() is false for a line that does not decode or
// holds a result no attempt gives (a thrower outside the act, negative switches).
std::string encode_result(const AttemptResult& r);
bool decode_result(const std::string& line, AttemptResult& r);

}  // namespace hil::trials
