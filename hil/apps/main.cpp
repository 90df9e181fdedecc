// The HIL executable: `hil <subcommand> [arguments]`. The subcommands live in cmd_<name>.cpp
// and are declared in commands.hpp; adding one is one line in kSubcommands.
#include "hil/apps/commands.hpp"
#include "pa/command_line.hpp"
#ifdef PA_HIL_RUN
#include "hil/run/cmd_run.hpp"
#endif

namespace {

constexpr pa::cli::Subcommand kSubcommands[] = {
    {"record", "run a scenario on the truth plant and write the motion-capture log as CSV",
     hil::apps::cmd_record},
    {"fly", "fly a series of throws in the lockstep arena with the ground-station runtime",
     hil::apps::cmd_fly},
    {"campaign", "fly many independent attempts on randomised plants, in parallel, with a summary",
     hil::apps::cmd_campaign},
    {"cuts", "cut the setpoint stream at drawn instants of the mission and judge the failsafe landings",
     hil::apps::cmd_cuts},
    {"config", "print the plant parameters (optionally randomised from a seed)", hil::apps::cmd_config},
#ifdef PA_HIL_RUN
    {"run", "run the truth plant as a process between fw_vehicle processes and groundstation run",
     hil::run::cmd_run},
#endif
};

}  // namespace

int main(int argc, char** argv) { return pa::cli::run_subcommand("hil", kSubcommands, argc, argv); }
