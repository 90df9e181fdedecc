#include "groundstation/link/mission_commands.hpp"

namespace gs::link {

bool MissionCommands::settle(CommandState state, bool arming) {
  if (!pending_ || state == CommandState::pending) return false;
  pending_.reset();
  if (state != CommandState::accepted) {
    failed_ = true;
    arm_after_disarm_ = false;
    return false;
  }
  if (!arm_after_disarm_) return false;
  arm_after_disarm_ = false;
  return arming;
}

}  // namespace gs::link
