#include "groundstation/adaptation/catch_energy.hpp"

#include <algorithm>
#include <cmath>

namespace gs::adaptation {

double CatchEnergyCorrection::height_offset_m(pa::VehicleId catcher) const {
  return pa::is_act_vehicle(catcher) ? offset_m_[pa::act_slot(catcher)] : 0.0;
}

bool CatchEnergyCorrection::learn(pa::VehicleId catcher, double energy_J, double target_energy_J) {
  const double error_J = energy_J - target_energy_J;
  if (!pa::is_act_vehicle(catcher) || !std::isfinite(error_J) || std::abs(error_J) > settings_.max_error_J)
    return false;
  double& offset = offset_m_[pa::act_slot(catcher)];
  offset = std::clamp(offset + settings_.gain * error_J / settings_.sensitivity_J_per_m,
                      -settings_.max_offset_m, settings_.max_offset_m);
  return true;
}

}  // namespace gs::adaptation
