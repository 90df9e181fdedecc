// Fuzzes the motion-capture CSV reader: every line through parse_mocap_row/is_mocap_header, then the
// whole input replayed through the estimator (replay_mocap_log, the `groundstation estimate`
// path), which must never throw on bad input.
//
// Invariants: a row that parses has a finite time and position and a unit quaternion (the
// estimator relies on both); a row that does not parse says why; the replay's counts add up.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>
#include <string_view>

#include "groundstation/estimation/mocap_log.hpp"

namespace {

void check(bool condition) {
  if (!condition) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);

  std::string_view rest = text;
  while (!rest.empty()) {
    const std::size_t end = rest.find('\n');
    const std::string_view line = rest.substr(0, end);
    rest.remove_prefix(end == std::string_view::npos ? rest.size() : end + 1);
    if (gs::estimation::is_mocap_header(line)) continue;
    const gs::estimation::MocapRowParse parsed = gs::estimation::parse_mocap_row(line);
    if (!parsed.row) {
      check(!parsed.error.empty());
      continue;
    }
    const gs::estimation::MocapRow& row = *parsed.row;
    check(std::isfinite(row.t_s) && row.pose.p_m.allFinite());
    check(std::abs(row.pose.q.norm() - 1.0) < 1e-9);
  }

  std::istringstream in(text);
  std::ostringstream out;
  std::ostringstream diagnostics;
  gs::estimation::ReplayOptions options;
  options.catch_height_m = 1.3;
  const gs::estimation::ReplaySummary summary =
      gs::estimation::replay_mocap_log(in, out, diagnostics, options);
  check(summary.rows <= summary.lines);
  check(summary.pole_frames <= summary.frames);
  check(summary.ok || !summary.fatal_error.empty());
  return 0;
}
