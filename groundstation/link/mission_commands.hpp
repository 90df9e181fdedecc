// One vehicle's mission commands as the runtime sequences them (ARM, DISARM, LAND, EXPECT_CATCH,
// CATCH_HANDLED; GroundLink::send_command carries and retries them): the one in flight, whether
// the last one failed (the sequencer's command_failed), and the protocol's DISARM-then-ARM for a
// vehicle that landed, which arms only from disarmed (fw/supervisor.hpp). It sends nothing
// itself: it tells the runtime when the ARM is due (mission_commands_test.cpp).
#pragma once

#include <optional>

#include "groundstation/link/ground_link.hpp"

namespace gs::link {

class MissionCommands {
 public:
  // Arming starts afresh: no failure; `disarm_first` when a DISARM goes ahead of the ARM.
  void arming(bool disarm_first) {
    failed_ = false;
    arm_after_disarm_ = disarm_first;
  }
  void sent(const CommandHandle& handle) { pending_ = handle; }

  // The command in flight has come to `state` (as the link knows it). True when the ARM is due
  // now: the DISARM ahead of it was accepted and the vehicle is still `arming`.
  bool settle(CommandState state, bool arming);

  const std::optional<CommandHandle>& pending() const { return pending_; }
  bool failed() const { return failed_; }
  bool arm_after_disarm() const { return arm_after_disarm_; }

 private:
  std::optional<CommandHandle> pending_;
  bool failed_ = false;
  bool arm_after_disarm_ = false;  // a DISARM in flight clears `landed` for the ARM that follows
};

}  // namespace gs::link
