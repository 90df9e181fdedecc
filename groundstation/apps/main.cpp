// The operator's executable: `groundstation <subcommand> [arguments]`. The subcommands live in
// cmd_<name>.cpp and are declared in commands.hpp; adding one is one line in kSubcommands. run, op
// and watch (groundstation/service) need Cyclone DDS and are there only when it was found.
#include "groundstation/apps/commands.hpp"
#include "pa/command_line.hpp"

namespace {

constexpr pa::cli::Subcommand kSubcommands[] = {
    {"adaptation", "show or reset the adapted catch (VI); show the motor identifications",
     gs::apps::cmd_adaptation},
    {"catch-instant", "the optimal catching instant (42), catching height and catch point (III-B)",
     gs::apps::cmd_catch_instant},
    {"estimate", "replay a motion-capture log through the estimator (IV) and write the pole estimate",
     gs::apps::cmd_estimate},
    {"history", "list the recorded throws and motor identifications of an adaptation store (table or CSV)",
     gs::apps::cmd_history},
#ifdef PA_GROUNDSTATION_SERVICE
    {"op", "send an operator command (take-off, land, abort, throw, kill) and print its answer",
     gs::apps::cmd_op},
#endif
    {"plan-catch", "plan the catch manoeuvre (Section V) and write it as CSV", gs::apps::cmd_plan_catch},
    {"plan-throw", "solve the optimal throw (34) with its TV-LQR gains and write CSVs",
     gs::apps::cmd_plan_throw},
#ifdef PA_GROUNDSTATION_SERVICE
    {"run", "run the ground station between the ground CAN bus and the arena's DDS domain",
     gs::apps::cmd_run},
    {"watch", "show the vehicles, the pole and the latest events of a running ground station",
     gs::apps::cmd_watch},
#endif
};

}  // namespace

int main(int argc, char** argv) { return pa::cli::run_subcommand("groundstation", kSubcommands, argc, argv); }
