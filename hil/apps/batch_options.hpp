// The options of the subcommands that fly many runs on worker processes (`hil campaign`,
// `hil cuts`): --out DIR, --seed S, --plant FILE, --jobs J, and what they need before a run.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "hil/plant/plant_config.hpp"
#include "pa/command_line.hpp"

namespace hil::apps {

struct BatchOptions {
  std::string out_dir;
  std::uint64_t seed = 1;
  std::string plant_file;
  std::uint64_t jobs = 0;  // 0: every core
};

// Adds the four options; `writes` completes "--out DIR: write DIR/..." and `seeds` what S seeds.
void add_batch_options(CLI::App& app, BatchOptions& options, const std::string& writes,
                       const std::string& seeds);

// Loads the plant (the built-in one without --plant), creates DIR and resolves J. On failure
// prints "<tool>: <message>" on stderr and returns the exit code (2 for a bad plant file, 1 for
// a folder that cannot be created).
std::optional<int> prepare_batch(const std::string& tool, const BatchOptions& options, PlantConfig& plant,
                                 int& jobs);

}  // namespace hil::apps
