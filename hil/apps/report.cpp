#include "hil/apps/report.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <vector>

namespace hil::apps {
namespace {

// The script's exit code when matplotlib cannot be imported (make_report.py).
constexpr int kNoMatplotlib = 3;
// What a child that could not start python3 exits with, as a shell would.
constexpr int kNotFound = 127;

// The script beside the sources, or where PA_HIL_REPORT_SCRIPT (an environment variable) says.
std::string report_script() {
  if (const char* over = std::getenv("PA_HIL_REPORT_SCRIPT"); over != nullptr && *over != '\0') return over;
  return PA_HIL_REPORT_SCRIPT;
}

// Debian's python3 first: python3-matplotlib installs for it, and a python3 earlier on PATH (a
// pyenv or a virtual environment) may not have it. PA_HIL_PYTHON names another interpreter.
std::string python() {
  if (const char* over = std::getenv("PA_HIL_PYTHON"); over != nullptr && *over != '\0') return over;
  if (::access("/usr/bin/python3", X_OK) == 0) return "/usr/bin/python3";
  return "python3";
}

}  // namespace

bool make_report(const std::string& out_dir, const std::string& tool) {
  const std::string script = report_script();
  if (!std::filesystem::exists(script)) {
    std::cerr << tool << ": warning: no report: the report script '" << script
              << "' is missing; the CSV files are in " << out_dir << "\n";
    return false;
  }
  const std::string interpreter = python();
  std::vector<char*> args{const_cast<char*>(interpreter.c_str()), const_cast<char*>(script.c_str()),
                          const_cast<char*>(out_dir.c_str()), nullptr};
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) {
    std::cerr << tool << ": warning: no report: cannot start python3\n";
    return false;
  }
  if (pid == 0) {
    ::execvp(interpreter.c_str(), args.data());
    ::_exit(kNotFound);
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
  }
  const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  if (code == 0) return true;
  if (code == kNotFound) {
    std::cerr << tool << ": warning: no report: python3 was not found (install python3 and "
              << "python3-matplotlib, e.g. scripts/install-deps.sh); the CSV files are in " << out_dir
              << "\n";
  } else if (code == kNoMatplotlib) {
    std::cerr << tool << ": warning: no report: matplotlib is missing (install the Debian package "
              << "python3-matplotlib, e.g. scripts/install-deps.sh); the CSV files are in " << out_dir
              << "\n";
  } else {
    std::cerr << tool << ": warning: the report script failed (exit " << code << "); the CSV files are in "
              << out_dir << "\n";
  }
  return false;
}

}  // namespace hil::apps
