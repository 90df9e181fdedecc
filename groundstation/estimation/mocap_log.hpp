// Offline replay of a recorded motion-capture log through the estimator (`groundstation
// estimate`).
//
// Input CSV, one pose per row, header `t,body,x,y,z,qw,qx,qy,qz` (SI units; body is vehicle1,
// vehicle2 or pole; q turns body vectors into inertial ones, for the pole its z-axis into n).
// Rows with the same t form one motion-capture frame; the rows are replayed in time order (a row
// earlier than the one before it is reported and sorted into place). Malformed rows (wrong field
// count, a field that is not a finite number, an unknown body, a quaternion far from unit
// length, a body twice in one frame) are reported with their line number and skipped; the
// replay goes on. A pose that is well formed but wrong (a glitch) is left to the estimator's
// outlier rejection.
//
// Output CSV, one row per frame that holds the pole:
//   t,mode,px,py,pz,vx,vy,vz,nx,ny,nz,wx,wy,wz,catch_t,catch_x,catch_y
// with the chosen mode's estimate (n in the log's convention) and, in free flight, the predicted
// downward crossing of the catching height by the pole's lower end (planning::predict_catch_point
// with the estimated drag; catch_t on the log's clock); the catch columns are empty when no
// crossing is predicted.
#pragma once

#include <cstddef>
#include <iosfwd>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "groundstation/estimation/mocap_pose.hpp"
#include "groundstation/estimation/state_estimator.hpp"

namespace gs::estimation {

inline constexpr std::string_view kMocapLogHeader = "t,body,x,y,z,qw,qx,qy,qz";
inline constexpr std::string_view kEstimateLogHeader =
    "t,mode,px,py,pz,vx,vy,vz,nx,ny,nz,wx,wy,wz,catch_t,catch_x,catch_y";

enum class MocapBody { vehicle1, vehicle2, pole };

struct MocapRow {
  double t_s = 0.0;
  MocapBody body = MocapBody::pole;
  MocapPose pose;
};

struct MocapRowParse {
  std::optional<MocapRow> row;  // empty on error
  std::string error;            // what is wrong (without the line number)
};

// Parses one data row (no trailing newline; a trailing '\r' and spaces around fields are
// tolerated).
MocapRowParse parse_mocap_row(std::string_view line);
// True for the header row (spaces and a trailing '\r' tolerated).
bool is_mocap_header(std::string_view line);

struct ReplayOptions {
  double catch_height_m = 0.0;
  StateEstimatorConfig config;
  std::size_t max_reported_errors = 20;  // further problems are only counted
  // The file the stream reads: problems are then reported as "FILE:N: ..." (empty: "line N: ...").
  std::string source;
};

struct ReplaySummary {
  bool ok = false;  // false: nothing could be estimated (see fatal_error)
  std::string fatal_error;
  std::size_t lines = 0;
  std::size_t rows = 0;  // data rows read (well-formed or not)
  std::size_t malformed = 0;
  std::size_t reordered = 0;  // rows earlier than the row before them
  std::size_t frames = 0;
  std::size_t pole_frames = 0;
  std::size_t catch_predictions = 0;
  std::vector<ModeSwitch> switches;
  EstimatorHealth health;
};

// Replays `in` into `out` (the estimate CSV, header first); problems go to `diagnostics`, one
// line each ("line N: ...", or "FILE:N: ..." with options.source). Never throws on bad input.
ReplaySummary replay_mocap_log(std::istream& in, std::ostream& out, std::ostream& diagnostics,
                               const ReplayOptions& options);
// Replays the file at `path` (options.source becomes `path`); a file that cannot be opened is a
// fatal error ("cannot read 'PATH'").
ReplaySummary replay_mocap_log_file(const std::string& path, std::ostream& out, std::ostream& diagnostics,
                                    ReplayOptions options);

}  // namespace gs::estimation
