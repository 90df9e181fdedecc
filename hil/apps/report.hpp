// The report of `hil fly --out DIR` and `hil campaign --out DIR`: DIR/report.html with its
// figures, made by hil/report/make_report.py (Python 3 and matplotlib, Debian's
// python3-matplotlib) from the CSV files in DIR. See docs/report.md.
#pragma once

#include <string>

namespace hil::apps {

// Runs the report script on `out_dir`, its output passed through. When python3 or matplotlib is
// missing, or the script fails, prints a warning that names the package and returns false; the
// CSV files stay as they are, and the caller's exit status does not change.
bool make_report(const std::string& out_dir, const std::string& tool);

}  // namespace hil::apps
