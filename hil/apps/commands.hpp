// The subcommands of the `hil` executable, one file each (cmd_<name>.cpp), listed in the table
// in main.cpp. Each takes argv[0] = its own name and argv[1..] = its arguments, returns the
// process exit code (0 done, 2 bad arguments with a usage message on stderr) and never lets an
// exception escape (main.cpp also catches, as a last resort).
#pragma once

namespace hil::apps {

int cmd_record(int argc, char** argv);
int cmd_config(int argc, char** argv);
int cmd_fly(int argc, char** argv);
int cmd_campaign(int argc, char** argv);
int cmd_cuts(int argc, char** argv);

}  // namespace hil::apps
