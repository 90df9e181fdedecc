// The command lines of the host tools, parsed by CLI11. This adds what every tool shares: the
// help layout (the usage line first, as the tools always printed it), errors as
// "<tool> <subcommand>: <message naming the flag>" followed by the help on stderr with exit code
// 2, and the value checks whose messages name the flag ("--throws needs a count 1..100000, got
// '2x'"). Nothing here throws to the caller.
#pragma once

#include <CLI/CLI.hpp>

#include <cstdint>
#include <optional>
#include <ostream>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace pa::cli {

// Gives `app` the tools' help layout: `usage` (e.g. "usage: hil fly --throws N [--seed S]",
// one or more lines) first, then `description`, the options CLI11 lists, then `footer` (exit
// codes and the like).
void describe(CLI::App& app, std::string usage, std::string description, std::string footer = {});

// Parses the arguments after the command's own name (argv[0] is that name). nullopt: the values
// are set and the command runs. Otherwise the command's exit code: 0 after the help on `out`
// (--help, -h), 2 after "<app name>: <message>", a blank line and the help on `err`.
std::optional<int> parse(CLI::App& app, int argc, const char* const* argv, std::ostream& out,
                         std::ostream& err);
std::optional<int> parse(CLI::App& app, const std::vector<std::string>& args, std::ostream& out,
                         std::ostream& err);

// Value checks for add_option(...)->check(...). `need` continues the flag's name in the message:
// "--catch-height" + " must be a number (m)" + ", got 'abc'".
CLI::Validator finite_number(std::string need);                              // "1.5", "-2e-3"
CLI::Validator number_in(double lo, double hi, std::string need);            // and lo <= x <= hi
CLI::Validator count(std::uint64_t lo, std::uint64_t hi, std::string need);  // decimal digits only
CLI::Validator number_pair(std::string need);                                // "A,B"
CLI::Validator one_of(std::vector<std::string> choices, std::string need);
CLI::Validator non_empty(std::string need);

// "A,B" as two numbers; call only on text that number_pair() accepted (otherwise {0, 0}).
struct NumberPair {
  double first = 0.0;
  double second = 0.0;
};
NumberPair to_number_pair(const std::string& text);

// `<program> <subcommand> [arguments]`, the dispatcher of groundstation and hil. Each subcommand
// takes argv[0] = its own name and argv[1..] = its arguments and returns the process exit code
// (0 done, 1 failed, 2 bad arguments).
struct Subcommand {
  std::string_view name;
  std::string_view help;  // one line
  int (*run)(int argc, char** argv);
};

// Runs the subcommand argv[1] names. No subcommand, `help`, `--help` or `-h` lists the table on
// stdout (exit 0); `help <subcommand>` runs `<subcommand> --help`; an unknown name is an error
// with the list on stderr (exit 2). An exception escaping a subcommand is reported as an internal
// error (exit 1): the process never dies on one.
int run_subcommand(std::string_view program, std::span<const Subcommand> table, int argc, char** argv);

}  // namespace pa::cli
