// One finished motor identification as the adaptation store keeps it (estimation/rate_response.hpp,
// runtime/identification_flight.hpp): which vehicle, when, the outcome (identified, or the
// refusal's reason), the fit (the motors' time constant with its 95 % interval, the inertia's
// error, the radio's round trip, the residual) and the vehicle's thrust gain at that moment when
// it had been measured (estimation/thrust_gain.hpp).
//
// Why it is kept. A take-off's fit can be refused (no telemetry, saturated motors, no motion, a
// lag at the search's edge, an interval too wide); the vehicle then flies with the last accepted
// identification, which may be one of an earlier run: the store is how it survives a restart
// (adaptation/identification_memory.hpp decides what is set on board). The refusals are kept too,
// so that an operator sees a vehicle whose fits keep failing (`groundstation adaptation`).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "groundstation/estimation/rate_response.hpp"
#include "pa/vehicle_id.hpp"

namespace gs::adaptation {

struct IdentificationRecord {
  pa::VehicleId vehicle = pa::kVehicle1;
  double time_s = 0.0;  // ground-station time the fit finished, as the caller passes it
  estimation::IdentificationResult result;
  std::optional<double> thrust_gain;  // k at that moment, when it had been measured in flight
};

struct StoredIdentification {
  std::int64_t id = 0;  // 1, 2, ... in recording order, over all vehicles
  IdentificationRecord record;
  bool accepted() const { return record.result.identified.has_value(); }
};

// "identified", or the refusal's name (estimation::refusal_name): the store's, the CLI's.
std::string_view outcome_name(const estimation::IdentificationResult& result);
// The refusal an outcome name stands for (none for "identified"); nullopt for an unknown name.
std::optional<estimation::IdentificationRefusal> parse_identification_outcome(std::string_view name);

// An empty string if the record can be stored, else what is wrong: a vehicle that is no vehicle's
// node, a non-finite or negative figure, an interval that does not hold its lag, a result that is
// both refused and fitted or neither, a thrust gain that is not positive.
std::string validate(const IdentificationRecord& record);

}  // namespace gs::adaptation
