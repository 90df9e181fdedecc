// The operator's executable: `groundstation <subcommand> [arguments]`. The subcommands live in
// cmd_<name>.cpp and are declared in commands.hpp; adding one is one line in kSubcommands.
#include "groundstation/apps/commands.hpp"
#include "pa/command_line.hpp"

namespace {

constexpr pa::cli::Subcommand kSubcommands[] = {
    {"adaptation", "show or reset the adapted catching height, waiting point and offset bias (VI)",
     gs::apps::cmd_adaptation},
    {"catch-instant", "the optimal catching instant (42), catching height and catch point (III-B)",
     gs::apps::cmd_catch_instant},
    {"estimate", "replay a motion-capture log through the estimator (IV) and write the pole estimate",
     gs::apps::cmd_estimate},
    {"history", "list the recorded throws of an adaptation store (table or CSV)", gs::apps::cmd_history},
    {"plan-catch", "plan the catch manoeuvre (Section V) and write it as CSV", gs::apps::cmd_plan_catch},
    {"plan-throw", "solve the optimal throw (34) with its TV-LQR gains and write CSVs",
     gs::apps::cmd_plan_throw},
};

}  // namespace

int main(int argc, char** argv) { return pa::cli::run_subcommand("groundstation", kSubcommands, argc, argv); }
