// The adaptation store as a person reads it: the throw history as a table or as CSV, and the
// adapted values with what they rest on. Pure formatting; `groundstation history` and
// `groundstation adaptation` (adaptation_cli.hpp) print these.
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "groundstation/adaptation/adaptation_store.hpp"

namespace gs::adaptation {

// A fixed-width table, one line per throw, "-" where a figure is absent. Columns: id, launch
// time, outcome, launch position and velocity, alpha and its rate, the catching height used, the
// predicted and the actual catch point with their times after the launch, the optimal catch
// (42) (height, point, time), the bias sample (catcher minus target), |E - E*| and the note.
void write_history_table(std::ostream& out, const std::vector<StoredThrow>& throws);

// The column names of write_history_csv's header row.
std::string history_csv_header();
// A header row and one row per throw with every stored column and the bias sample (SI units,
// each number the shortest text that reads back as the same double, empty where absent; the
// note quoted as RFC 4180 asks when it holds a comma, a quote or a line break).
void write_history_csv(std::ostream& out, const std::vector<StoredThrow>& throws);

// The motor identifications (identification_record.hpp), one line each, "-" where a refused fit
// has no figure. Columns: id, vehicle, time, outcome (identified or the refusal), the lag and its
// 95 % interval in ms, the inertia's error, the round trip in ms, the residual, the samples and
// the thrust gain k.
void write_identification_table(std::ostream& out, const std::vector<StoredIdentification>& identifications);
// A header row and one row per identification with every stored column (SI units, exact, empty
// where absent).
std::string identification_csv_header();
void write_identification_csv(std::ostream& out, const std::vector<StoredIdentification>& identifications);
// Per vehicle: its last accepted identification (lag and interval, inertia, round trip, thrust
// gain, which and when) and, when its latest was refused, that refusal.
void write_identification_summary(std::ostream& out, const std::vector<VehicleIdentifications>& vehicles);

// The adapted catching height, waiting point and offset bias, how many throws they rest on,
// the nominal values, the window, and the consistency verdict.
void write_adaptation_summary(std::ostream& out, const std::string& path, const AdaptationSettings& settings,
                              const AdaptationSnapshot& snapshot, const ConsistencyReport& consistency);

}  // namespace gs::adaptation
