// What `hil fly` and `hil campaign --replay` write and print of a flown attempt: its time series
// (columns: docs/report.md) and what the ground station identified beside the plant's truth.
#pragma once

#include <string>
#include <vector>

#include "groundstation/runtime/ground_station.hpp"
#include "hil/plant/plant.hpp"
#include "hil/trials/series.hpp"

namespace hil::apps {

// One attempt's time series as DIR/attempt_<n>.csv.
void write_time_series(const std::string& path, const std::vector<trials::TimeSample>& samples);

// What the ground station identified of each vehicle's motors at its take-off, beside the truth
// of the plant it flew (which the ground station never sees).
void print_identification(const gs::runtime::GroundStation& gs, const Plant& truth);

}  // namespace hil::apps
