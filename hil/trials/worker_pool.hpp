// Independent jobs run on forked worker processes, their results reported as text lines.
//
// Processes, not threads: the throw's optimiser (IPOPT with MUMPS) keeps global state and is not
// safe to run in two threads of one process. Worker k (1..J) runs the k-th item, the (k + J)-th, ...
// and writes one line per item on its pipe; the parent reads them in order of completion. Which
// worker runs an item does not change its result, so a caller whose items depend on their index
// alone gets the same results whatever J is.
#pragma once

#include <functional>
#include <string>

namespace hil::trials {

// Runs items first..first + items - 1 on `jobs` worker processes. `run(i)` is called in a worker
// and returns item i's report (one line: no '\n'); `on_report(i, line)` is called in the calling
// process for each report, in order of completion (it may throw: the pool stops). Throws
// std::runtime_error when items or jobs is below 1, when a worker cannot be started, or when
// one dies without reporting all of its items (`noun` names an item in that message).
void run_on_workers(int items, int jobs, const std::function<std::string(int item)>& run,
                    const std::function<void(int item, const std::string& report)>& on_report,
                    const std::string& noun = "item", int first = 1);

}  // namespace hil::trials
