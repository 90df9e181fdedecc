// `groundstation adaptation`: the adapted catching height, waiting position and catcher offset
// bias of Section VI, and their reset (groundstation/adaptation/adaptation_cli.hpp).
#include <iostream>

#include "groundstation/adaptation/adaptation_cli.hpp"
#include "groundstation/apps/commands.hpp"

namespace gs::apps {

int cmd_adaptation(int argc, char** argv) {
  return adaptation::run_adaptation_command(argc, argv, std::cout, std::cerr);
}

}  // namespace gs::apps
