#include "fw/failsafe_controller.hpp"

namespace fw {

FailsafeController::FailsafeController(const SupervisorConfig& config)
    : level_gain_per_s_(config.level_gain_per_s),
      descent_rate_mps_(config.descent_rate_mps),
      ground_contact_mps2_(config.ground_contact_mps2),
      ground_contact_us_(static_cast<float>(config.ground_contact_us)) {}

}  // namespace fw
