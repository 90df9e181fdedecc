// `hil record --scenario FILE --out FILE.csv [...]`: the work is in hil/plant/recorder.cpp so
// that tests can run it in-process.
#include <iostream>
#include <string>
#include <vector>

#include "hil/apps/commands.hpp"
#include "hil/plant/recorder.hpp"

namespace hil::apps {

int cmd_record(int argc, char** argv) {
  std::vector<std::string> args;
  for (int i = 1; i < argc; ++i) args.emplace_back(argv[i]);
  return record_command(args, std::cout, std::cerr);
}

}  // namespace hil::apps
