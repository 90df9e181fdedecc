#include "groundstation/adaptation/identification_memory.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace gs::adaptation {

IdentificationMemory::IdentificationMemory(const IdentificationMemorySettings& settings,
                                           const std::string& store_path,
                                           const AdaptationSettings& adaptation)
    : settings_(settings) {
  if (store_path.empty()) return;
  store_.emplace(AdaptationStore::open_or_create(store_path, adaptation));
  for (const VehicleIdentifications& v : store_->identifications_by_vehicle()) {
    if (v.last_accepted) slot(v.vehicle) = v.last_accepted->record.result.identified;
  }
}

std::optional<estimation::MotorIdentification>& IdentificationMemory::slot(pa::VehicleId vehicle) {
  if (!vehicle.valid()) throw std::out_of_range("no vehicle with node " + std::to_string(vehicle.node()));
  return kept_[vehicle.node()];
}

const std::optional<estimation::MotorIdentification>& IdentificationMemory::kept(
    pa::VehicleId vehicle) const {
  return const_cast<IdentificationMemory*>(this)->slot(vehicle);
}

// The tolerance is a fraction of the lag to set, as the fit's accuracy is of the lag it finds.
bool IdentificationMemory::differs(double lag_s, double from_s) const {
  return std::abs(lag_s - from_s) > settings_.tolerance_fraction * lag_s;
}

std::optional<double> IdentificationMemory::lag_at_arming(pa::VehicleId vehicle) const {
  const std::optional<estimation::MotorIdentification>& k = kept(vehicle);
  if (!k || !differs(k->time_constant_s, settings_.design_time_constant_s)) return std::nullopt;
  return k->time_constant_s;
}

std::optional<double> IdentificationMemory::inertia_scale_to_set(pa::VehicleId vehicle,
                                                                 double on_board) const {
  const std::optional<estimation::MotorIdentification>& k = kept(vehicle);
  if (!k || !(k->inertia_gain > 0.0)) return std::nullopt;
  const double scale = std::min(1.0 / k->inertia_gain, settings_.max_inertia_scale);
  if (!differs(scale, on_board)) return std::nullopt;
  return scale;
}

std::optional<double> IdentificationMemory::finished(pa::VehicleId vehicle,
                                                     const estimation::IdentificationResult& result,
                                                     std::optional<double> thrust_gain, double now_s,
                                                     double equalised_s) {
  const IdentificationRecord record{vehicle, now_s, result, thrust_gain};
  if (!validate(record).empty()) return std::nullopt;
  if (store_) store_->record_identification(record);
  if (!result.identified) return std::nullopt;
  slot(vehicle) = result.identified;
  const double lag_s = result.identified->time_constant_s;
  if (!differs(lag_s, equalised_s)) return std::nullopt;
  return lag_s;
}

}  // namespace gs::adaptation
