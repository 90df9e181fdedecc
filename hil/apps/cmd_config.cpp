// `hil config [--plant FILE] [--seed N] [--randomise]`: prints the plant parameters a run would
// use, as a loadable `key = value` file.
#include <exception>
#include <iostream>
#include <string>

#include "hil/apps/commands.hpp"
#include "hil/plant/key_value_file.hpp"
#include "hil/plant/plant_config.hpp"
#include "hil/plant/randomisation.hpp"

namespace hil::apps {

namespace {
void usage(std::ostream& out) {
  out << "usage: hil config [--plant FILE] [--seed N] [--randomise]\n"
         "Prints the plant parameters (defaults, or FILE), randomised from the seed with --randomise.\n";
}
}  // namespace

int cmdConfig(int argc, char** argv) {
  std::string plant_path;
  std::uint64_t seed = 1;
  bool randomise = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") {
      usage(std::cout);
      return 0;
    }
    if (a == "--randomise") {
      randomise = true;
    } else if ((a == "--plant" || a == "--seed") && i + 1 < argc) {
      const std::string v = argv[++i];
      if (a == "--plant") {
        plant_path = v;
      } else {
        const auto n = parse_integer(v);
        if (!n || *n < 0) {
          std::cerr << "hil config: --seed needs a non-negative integer, got '" << v << "'\n";
          return 2;
        }
        seed = static_cast<std::uint64_t>(*n);
      }
    } else {
      std::cerr << "hil config: bad argument '" << a << "'\n\n";
      usage(std::cerr);
      return 2;
    }
  }
  PlantConfig config;
  std::string error;
  if (!plant_path.empty() && !load_plant_config(plant_path, config, error)) {
    std::cerr << "hil config: " << error << "\n";
    return 2;
  }
  if (randomise) config = randomised(config, seed);
  std::cout << format_plant_config(config);
  return 0;
}

}  // namespace hil::apps
