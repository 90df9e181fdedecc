// The operator's view of the adaptation store: `groundstation history` and `groundstation
// adaptation` (groundstation/apps/cmd_history.cpp, cmd_adaptation.cpp call these). They live in
// the library so the tests can run them in-process. Exit codes: 0 done, 1 a missing, foreign or
// damaged store (a message naming the file on err), 2 bad arguments (a usage message on err).
// No exception escapes.
#pragma once

#include <ostream>

namespace gs::adaptation {

// history --db FILE [--last N] [--csv]
int run_history_command(int argc, const char* const* argv, std::ostream& out, std::ostream& err);

// adaptation --db FILE [--reset --yes]
int run_adaptation_command(int argc, const char* const* argv, std::ostream& out, std::ostream& err);

}  // namespace gs::adaptation
