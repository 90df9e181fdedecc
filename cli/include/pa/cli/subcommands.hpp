// `<program> <subcommand> [arguments]`: the dispatcher of the host tools. Each subcommand takes
// argv[0] = its own name and argv[1..] = its arguments and returns the process exit code
// (0 done, 1 failed, 2 bad arguments with a usage message on stderr).
#pragma once

#include <span>
#include <string_view>

namespace pa::cli {

struct Subcommand {
  std::string_view name;
  std::string_view help;  // one line
  int (*run)(int argc, char** argv);
};

// Runs the subcommand argv[1] names. No subcommand, `help`, `--help` or `-h` lists the table on
// stdout (exit 0); `help <subcommand>` runs `<subcommand> --help`; an unknown name lists it on
// stderr (exit 2). An exception escaping a subcommand is reported as an internal error (exit 1):
// the process never dies on one.
int runSubcommand(std::string_view program, std::span<const Subcommand> table, int argc,
                  char** argv);

}  // namespace pa::cli
