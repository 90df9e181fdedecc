// One vehicle's mission commands (groundstation/link/mission_commands.hpp): a command in flight
// until the link settles it, a failure remembered until the next arming, and the ARM that
// follows an accepted DISARM while the vehicle still arms.
#include <catch2/catch.hpp>

#include "groundstation/link/mission_commands.hpp"

namespace {

using gs::link::CommandHandle;
using gs::link::CommandState;
using gs::link::MissionCommands;

CommandHandle handle(std::uint32_t serial) {
  CommandHandle h;
  h.vehicle = pa::kVehicle1;
  h.serial = serial;
  return h;
}

}  // namespace

TEST_CASE("Nothing in flight: nothing to settle") {
  MissionCommands commands;
  CHECK_FALSE(commands.pending());
  CHECK_FALSE(commands.settle(CommandState::accepted, true));
  CHECK_FALSE(commands.failed());
}

TEST_CASE("A command stays in flight while pending, and is settled once") {
  MissionCommands commands;
  commands.sent(handle(1));
  CHECK_FALSE(commands.settle(CommandState::pending, false));
  REQUIRE(commands.pending());
  CHECK(commands.pending()->serial == 1);
  CHECK_FALSE(commands.settle(CommandState::accepted, false));
  CHECK_FALSE(commands.pending());
  CHECK_FALSE(commands.failed());
}

TEST_CASE("A refused or timed-out command fails until the next arming, and cancels the ARM after DISARM") {
  for (CommandState failure : {CommandState::refused, CommandState::timed_out}) {
    MissionCommands commands;
    commands.arming(true);
    commands.sent(handle(1));
    CHECK_FALSE(commands.settle(failure, true));
    CHECK(commands.failed());
    CHECK_FALSE(commands.arm_after_disarm());
    CHECK_FALSE(commands.pending());
    commands.arming(false);
    CHECK_FALSE(commands.failed());
  }
}

TEST_CASE("A landed vehicle: the accepted DISARM makes the ARM due, if it still arms") {
  MissionCommands commands;
  commands.arming(true);
  commands.sent(handle(1));
  CHECK(commands.arm_after_disarm());
  CHECK(commands.settle(CommandState::accepted, true));
  CHECK_FALSE(commands.arm_after_disarm());
  commands.sent(handle(2));                                    // the ARM
  CHECK_FALSE(commands.settle(CommandState::accepted, true));  // no second ARM

  MissionCommands gave_up;  // the sequencer left arming meanwhile: no ARM
  gave_up.arming(true);
  gave_up.sent(handle(3));
  CHECK_FALSE(gave_up.settle(CommandState::accepted, false));
  CHECK_FALSE(gave_up.arm_after_disarm());
}

TEST_CASE("An ARM without DISARM ahead: accepted, nothing follows") {
  MissionCommands commands;
  commands.arming(false);
  commands.sent(handle(1));
  CHECK_FALSE(commands.settle(CommandState::accepted, true));
  CHECK_FALSE(commands.failed());
}
