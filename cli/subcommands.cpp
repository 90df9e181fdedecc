#include "pa/cli/subcommands.hpp"

#include <cstdio>
#include <exception>

namespace pa::cli {

namespace {

int width(std::string_view s) { return static_cast<int>(s.size()); }

void printTable(std::FILE* out, std::string_view program, std::span<const Subcommand> table) {
  std::fprintf(out, "usage: %.*s <subcommand> [arguments]\n\nsubcommands:\n", width(program),
               program.data());
  std::fprintf(out, "  %-14s %s\n", "help", "this list; `help <subcommand>` for its arguments");
  for (const Subcommand& c : table) {
    std::fprintf(out, "  %-14.*s %.*s\n", width(c.name), c.name.data(), width(c.help),
                 c.help.data());
  }
}

const Subcommand* find(std::span<const Subcommand> table, std::string_view name) {
  for (const Subcommand& c : table) {
    if (c.name == name) return &c;
  }
  return nullptr;
}

int unknown(std::string_view program, std::span<const Subcommand> table, const char* name) {
  std::fprintf(stderr, "%.*s: unknown subcommand '%s'\n\n", width(program), program.data(), name);
  printTable(stderr, program, table);
  return 2;
}

int dispatch(std::string_view program, std::span<const Subcommand> table, int argc, char** argv) {
  if (argc < 2) {
    printTable(stdout, program, table);
    return 0;
  }
  const std::string_view name = argv[1];
  if (name == "help" || name == "--help" || name == "-h") {
    if (argc < 3) {
      printTable(stdout, program, table);
      return 0;
    }
    const Subcommand* c = find(table, argv[2]);
    if (c == nullptr) return unknown(program, table, argv[2]);
    char help_flag[] = "--help";
    char* sub_argv[] = {argv[2], help_flag, nullptr};
    return c->run(2, sub_argv);
  }
  const Subcommand* c = find(table, name);
  if (c == nullptr) return unknown(program, table, argv[1]);
  return c->run(argc - 1, argv + 1);
}

}  // namespace

int runSubcommand(std::string_view program, std::span<const Subcommand> table, int argc,
                  char** argv) {
  try {
    return dispatch(program, table, argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%.*s: internal error: %s\n", width(program), program.data(), e.what());
  } catch (...) {
    std::fprintf(stderr, "%.*s: internal error\n", width(program), program.data());
  }
  return 1;
}

}  // namespace pa::cli
