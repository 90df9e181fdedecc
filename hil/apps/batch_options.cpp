#include "hil/apps/batch_options.hpp"

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <iostream>

namespace hil::apps {

void add_batch_options(CLI::App& app, BatchOptions& options, const std::string& writes,
                       const std::string& seeds) {
  app.add_option("--out", options.out_dir, "write DIR/" + writes)->type_name("DIR")->required();
  app.add_option("--seed", options.seed, "seed of " + seeds + " (default 1)")
      ->type_name("S")
      ->check(pa::cli::count(0, UINT64_MAX, "needs a non-negative integer"));
  app.add_option("--plant", options.plant_file, "plant configuration (default: the built-in one)")
      ->type_name("FILE");
  app.add_option("--jobs", options.jobs, "worker processes (default: every core)")
      ->type_name("J")
      ->check(pa::cli::count(1, 256, "needs a count 1..256"));
}

std::optional<int> prepare_batch(const std::string& tool, const BatchOptions& options, PlantConfig& plant,
                                 int& jobs) {
  if (!options.plant_file.empty()) {
    std::string error;
    if (!load_plant_config(options.plant_file, plant, error)) {
      std::cerr << tool << ": " << error << "\n";
      return 2;
    }
  }
  std::error_code ec;
  std::filesystem::create_directories(options.out_dir, ec);
  if (ec) {
    std::cerr << tool << ": cannot create '" << options.out_dir << "': " << ec.message() << "\n";
    return 1;
  }
  const long cores = ::sysconf(_SC_NPROCESSORS_ONLN);
  jobs = options.jobs > 0 ? static_cast<int>(options.jobs) : static_cast<int>(std::max(1L, cores));
  return std::nullopt;
}

}  // namespace hil::apps
