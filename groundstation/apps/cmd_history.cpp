// `groundstation history`: the throws recorded in the adaptation store, as a table or CSV
// (groundstation/adaptation/adaptation_cli.hpp holds the command so the tests can run it).
#include <iostream>

#include "groundstation/adaptation/adaptation_cli.hpp"
#include "groundstation/apps/commands.hpp"

namespace gs::apps {

int cmd_history(int argc, char** argv) {
  return adaptation::run_history_command(argc, argv, std::cout, std::cerr);
}

}  // namespace gs::apps
