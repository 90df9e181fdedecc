// The operator's executable: `groundstation <subcommand> [arguments]`. The subcommands live in
// cmd_<name>.cpp and are declared in commands.hpp; adding one is one line in kSubcommands.
#include <cstdio>
#include <exception>
#include <string_view>

#include "groundstation/apps/commands.hpp"

namespace {

struct Subcommand {
  std::string_view name;
  std::string_view help;  // one line
  int (*run)(int argc, char** argv);
};

constexpr Subcommand kSubcommands[] = {
    {"adaptation", "show or reset the adapted catching height, waiting point and offset bias (VI)", gs::apps::cmdAdaptation},
    {"catch-instant", "the optimal catching instant (42), catching height and catch point (III-B)", gs::apps::cmdCatchInstant},
    {"history", "list the recorded throws of an adaptation store (table or CSV)", gs::apps::cmdHistory},
    {"plan-catch", "plan the catch manoeuvre (Section V) and write it as CSV", gs::apps::cmdPlanCatch},
    {"plan-throw", "solve the optimal throw (34) with its TV-LQR gains and write CSVs", gs::apps::cmdPlanThrow},
};

void printSubcommands(std::FILE* out) {
  std::fprintf(out, "usage: groundstation <subcommand> [arguments]\n\nsubcommands:\n");
  std::fprintf(out, "  %-16s %s\n", "help", "this list; `help <subcommand>` for its arguments");
  for (const Subcommand& c : kSubcommands) {
    std::fprintf(out, "  %-16.*s %.*s\n", static_cast<int>(c.name.size()), c.name.data(),
                 static_cast<int>(c.help.size()), c.help.data());
  }
}

const Subcommand* find(std::string_view name) {
  for (const Subcommand& c : kSubcommands) {
    if (c.name == name) return &c;
  }
  return nullptr;
}

int dispatch(int argc, char** argv) {
  if (argc < 2) {
    printSubcommands(stdout);
    return 0;
  }
  const std::string_view name = argv[1];
  if (name == "help" || name == "--help" || name == "-h") {
    if (argc >= 3) {
      if (const Subcommand* c = find(argv[2])) {
        char help_flag[] = "--help";
        char* sub_argv[] = {argv[2], help_flag, nullptr};
        return c->run(2, sub_argv);
      }
      std::fprintf(stderr, "groundstation: unknown subcommand '%s'\n\n", argv[2]);
      printSubcommands(stderr);
      return 2;
    }
    printSubcommands(stdout);
    return 0;
  }
  if (const Subcommand* c = find(name)) return c->run(argc - 1, argv + 1);
  std::fprintf(stderr, "groundstation: unknown subcommand '%s'\n\n", argv[1]);
  printSubcommands(stderr);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return dispatch(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "groundstation: internal error: %s\n", e.what());
  } catch (...) {
    std::fprintf(stderr, "groundstation: internal error\n");
  }
  return 1;
}
