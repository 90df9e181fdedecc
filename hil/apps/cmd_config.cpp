// `hil config [--plant FILE] [--seed N] [--randomise]`: prints the plant parameters a run would
// use, as a loadable YAML file (the format of hil/config/plant.yaml).
#include <exception>
#include <iostream>
#include <string>

#include "hil/apps/commands.hpp"
#include "hil/plant/plant_config.hpp"
#include "hil/plant/randomisation.hpp"
#include "pa/command_line.hpp"

namespace hil::apps {

int cmd_config(int argc, char** argv) {
  std::string plant_path;
  std::uint64_t seed = 1;
  bool randomise = false;
  CLI::App app("", "hil config");
  pa::cli::describe(
      app, "usage: hil config [--plant FILE] [--seed N] [--randomise]",
      "Prints the plant parameters (defaults, or FILE), randomised from the seed with --randomise.");
  app.add_option("--plant", plant_path, "plant configuration to start from")->type_name("FILE");
  app.add_option("--seed", seed, "seed of --randomise (default 1)")
      ->type_name("N")
      ->check(pa::cli::count(0, UINT64_MAX, "needs a non-negative integer"));
  app.add_flag("--randomise", randomise, "draw the uncertain parameters from the seed");
  if (const std::optional<int> code = pa::cli::parse(app, argc, argv, std::cout, std::cerr)) return *code;
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
