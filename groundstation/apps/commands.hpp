// The subcommands of the `groundstation` executable, one file each (cmd_<name>.cpp), listed in
// the table in main.cpp. Each takes argv[0] = its own name and argv[1..] = its arguments, returns
// the process exit code (0 done, 2 bad arguments with a usage message on stderr) and never lets
// an exception escape (main.cpp also catches, as a last resort).
#pragma once

namespace gs::apps {

int cmd_adaptation(int argc, char** argv);
int cmd_catch_instant(int argc, char** argv);
int cmd_estimate(int argc, char** argv);
int cmd_history(int argc, char** argv);
int cmd_plan_catch(int argc, char** argv);
int cmd_plan_throw(int argc, char** argv);
// groundstation/service/service_cli.cpp, built with Cyclone DDS only (PA_GROUNDSTATION_SERVICE).
int cmd_run(int argc, char** argv);
int cmd_op(int argc, char** argv);
int cmd_watch(int argc, char** argv);

}  // namespace gs::apps
