// The motion-capture log replay behind `groundstation estimate` (estimation/mocap_log.hpp):
// parsing, malformed rows with their line numbers, the output format, and a replay of a throw
// recorded in the truth world.
#include "groundstation/estimation/mocap_log.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "estimation_test_world.hpp"

namespace {

using gs::estimation::MocapBody;
using gs::estimation::parse_mocap_row;

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) out.push_back(line);
  return out;
}

std::vector<std::string> fields(const std::string& line) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    out.push_back(line.substr(start, comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

void write_row(std::ostream& out, double t, const char* body, const estimation_test::Pose& p) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "%.4f,%s,%.6f,%.6f,%.6f,%.9f,%.9f,%.9f,%.9f\n", t, body, p.p.x(), p.p.y(),
                p.p.z(), p.q.w(), p.q.x(), p.q.y(), p.q.z());
  out << buf;
}

}  // namespace

TEST_CASE("mocap rows parse, malformed ones say what is wrong", "[estimation]") {
  CHECK(gs::estimation::is_mocap_header("t,body,x,y,z,qw,qx,qy,qz"));
  CHECK(gs::estimation::is_mocap_header(" t, body ,x,y,z,qw,qx,qy,qz\r"));
  CHECK_FALSE(gs::estimation::is_mocap_header("t,body,x,y,z,qw,qx,qy"));

  const auto ok = parse_mocap_row("1.25,pole,0.1,-0.2,1.5,1,0,0,0");
  REQUIRE(ok.row);
  CHECK(ok.row->t_s == 1.25);
  CHECK(ok.row->body == MocapBody::pole);
  CHECK(ok.row->pose.p_m.y() == -0.2);
  const auto scaled = parse_mocap_row("0,vehicle2,0,0,0,0.9,0,0,0");  // normalised
  REQUIRE(scaled.row);
  CHECK(scaled.row->pose.q.norm() == Approx(1.0));

  // The row is rejected with a message that names what is wrong.
  const auto rejects = [](const char* row, const char* message) {
    return parse_mocap_row(row).error.find(message) != std::string::npos;
  };
  CHECK(rejects("1,pole,0,0,0,1,0,0", "expected 9 fields"));
  CHECK(rejects("1,pole,0,abc,0,1,0,0,0", "'y' is not a number"));
  CHECK(rejects("1,pole,0,0,nan,1,0,0,0", "'z' is not finite"));
  CHECK(rejects("1,vehicle3,0,0,0,1,0,0,0", "unknown body 'vehicle3'"));
  CHECK(rejects("1,pole,0,0,0,0,0,0,0", "quaternion"));
  CHECK(rejects("", "expected 9 fields"));
  // Values no clock and no arena has: a corrupt row.
  CHECK(rejects("1e300,pole,0,0,0,1,0,0,0", "'t' is out of range (|t| <= 1e+09)"));
  CHECK(rejects("1,pole,0,-2e4,0,1,0,0,0", "'y' is out of range"));
  CHECK(rejects("1,pole,0,0,0,3,0,0,0", "'qw' is out of range"));
  CHECK(parse_mocap_row("-86400,pole,-9999,0,0,1,0,0,0").row);
}

TEST_CASE("a log with malformed rows is replayed, each problem reported by line", "[estimation]") {
  std::istringstream in("t,body,x,y,z,qw,qx,qy,qz\n"
                        "0.000,vehicle1,0,0,1,1,0,0,0\n"
                        "0.000,pole,0,0,1.695,1,0,0,0\n"
                        "0.005,vehicle1,0,0,1,1,0,0,0\n"
                        "0.005,pole,0,0,1.695,1,0,0\n"  // line 5: a field short
                        "0.005,pole,0,0,1.695,1,0,0,0\n"
                        "0.005,pole,0,0,1.695,1,0,0,0\n"  // line 7: the pole twice
                        "0.004,vehicle2,3,0,1,1,0,0,0\n"  // line 8: backwards, sorted into place
                        "\n"
                        "0.010,vehicle1,0,0,1,1,0,0,0\n"
                        "0.010,pole,0,0,1.695,1,0,0,0\n"
                        "0.015,pole,0,0,1.695,1,x,0,0\n");  // line 12: not a number
  std::ostringstream out;
  std::ostringstream diag;
  gs::estimation::ReplayOptions options;
  options.catch_height_m = 1.0;
  const gs::estimation::ReplaySummary s = gs::estimation::replay_mocap_log(in, out, diag, options);
  const std::vector<std::string> d = lines(diag.str());
  REQUIRE(d.size() == 4);
  CHECK(d[0].rfind("line 5: expected 9 fields", 0) == 0);
  CHECK(d[1].rfind("line 8: t = 0.004000 is earlier than the row before it", 0) == 0);
  CHECK(d[2].rfind("line 12: field 'qx' is not a number", 0) == 0);
  CHECK(d[3].rfind("line 7: a second pose of the same body", 0) == 0);  // found while replaying
  CHECK(s.ok);
  CHECK(s.malformed == 3);
  CHECK(s.reordered == 1);
  CHECK(s.frames == 4);  // 0, 0.004 (vehicle 2 only), 0.005, 0.010
  CHECK(s.pole_frames == 3);
  const std::vector<std::string> o = lines(out.str());
  REQUIRE(o.size() == 4);
  CHECK(o[0] == gs::estimation::kEstimateLogHeader);
  for (std::size_t i = 1; i < o.size(); ++i) {
    const std::vector<std::string> f = fields(o[i]);
    REQUIRE(f.size() == 17);
    CHECK(f[1] == "on_vehicle1");  // the pole stands on vehicle 1's plate
    CHECK(f[14].empty());          // no crossing predicted while it rests there
  }
}

TEST_CASE("a log without a header or without pole rows is handled", "[estimation]") {
  {
    std::istringstream in("0,pole,0,0,2,1,0,0,0\n0.005,pole,0,0,2,1,0,0,0\n");
    std::ostringstream out;
    std::ostringstream diag;
    const auto s = gs::estimation::replay_mocap_log(in, out, diag, {});
    CHECK(s.ok);
    CHECK(diag.str().find("line 1: no header row") != std::string::npos);
    CHECK(s.pole_frames == 2);
  }
  {
    std::istringstream in("t,body,x,y,z,qw,qx,qy,qz\n0,vehicle1,0,0,1,1,0,0,0\ngarbage\n");
    std::ostringstream out;
    std::ostringstream diag;
    const auto s = gs::estimation::replay_mocap_log(in, out, diag, {});
    CHECK_FALSE(s.ok);
    CHECK(s.fatal_error == "no usable pole rows");
    CHECK(diag.str().find("line 3:") != std::string::npos);
  }
  {
    std::istringstream in("");
    std::ostringstream out;
    std::ostringstream diag;
    const auto s = gs::estimation::replay_mocap_log(in, out, diag, {});
    CHECK_FALSE(s.ok);
    CHECK(s.fatal_error == "no data rows");
  }
}

TEST_CASE("a log read from a file reports its problems as FILE:LINE", "[estimation]") {
  const std::string path = "estimation_mocap_log_test_bad.csv";  // in the test's working directory
  {
    std::FILE* f = std::fopen(path.c_str(), "w");
    REQUIRE(f != nullptr);
    std::fputs("t,body,x,y,z,qw,qx,qy,qz\n0,pole,0,0,2,1,0,0,0\n0.005,dog,0,0,2,1,0,0,0\n", f);
    std::fclose(f);
  }
  std::ostringstream out;
  std::ostringstream diag;
  const auto s = gs::estimation::replay_mocap_log_file(path, out, diag, {});
  std::remove(path.c_str());
  CHECK(s.ok);
  CHECK(s.malformed == 1);
  CHECK(diag.str().rfind(path + ":3: unknown body 'dog'", 0) == 0);

  const auto missing = gs::estimation::replay_mocap_log_file("/nonexistent/mocap.csv", out, diag, {});
  CHECK_FALSE(missing.ok);
  CHECK(missing.fatal_error == "cannot read '/nonexistent/mocap.csv'");
}

TEST_CASE("a recorded throw replays into modes and catch predictions", "[estimation]") {
  const estimation_test::Recording rec = estimation_test::record_throw(estimation_test::WorldParams{}, 3);
  REQUIRE(rec.launch_t);
  REQUIRE(rec.impact_t);
  std::stringstream log;
  log << gs::estimation::kMocapLogHeader << '\n';
  for (const estimation_test::Frame& f : rec.frames) {
    write_row(log, f.t_s, "vehicle1", f.vehicle[0]);
    write_row(log, f.t_s, "vehicle2", f.vehicle[1]);
    write_row(log, f.t_s, "pole", f.pole);
  }
  std::ostringstream out;
  std::ostringstream diag;
  gs::estimation::ReplayOptions options;
  options.catch_height_m = rec.catch_height;
  const gs::estimation::ReplaySummary s = gs::estimation::replay_mocap_log(log, out, diag, options);
  CHECK(s.ok);
  CHECK(s.malformed == 0);
  CHECK(diag.str().empty());
  const std::vector<std::string> o = lines(out.str());
  REQUIRE(o.size() == rec.frames.size() + 1);
  std::optional<double> launch;
  std::optional<double> impact;
  double error_at_100ms = -1.0;
  for (std::size_t i = 1; i < o.size(); ++i) {
    const std::vector<std::string> f = fields(o[i]);
    REQUIRE(f.size() == 17);
    const double t = std::stod(f[0]);
    if (!launch && f[1] == "free") launch = t;
    if (!impact && f[1] == "on_vehicle2") impact = t;
    if (launch && error_at_100ms < 0.0 && t >= *rec.launch_t + 0.1 && f[1] == "free") {
      REQUIRE_FALSE(f[14].empty());
      error_at_100ms = std::hypot(std::stod(f[15]) - rec.crossing->x, std::stod(f[16]) - rec.crossing->y);
    }
  }
  REQUIRE(launch);
  REQUIRE(impact);
  std::printf("replay without commands: launch detected %+.1f frames from the truth, impact %+.1f "
              "frames; catch point %.1f mm off at launch + 0.1 s\n",
              (*launch - *rec.launch_t) / 0.005, (*impact - *rec.impact_t) / 0.005, 1e3 * error_at_100ms);
  CHECK(*impact - *rec.impact_t <= 0.010 + 1e-9);
  CHECK(*launch - *rec.launch_t >= -0.010);
  CHECK(error_at_100ms >= 0.0);
  CHECK(error_at_100ms < 0.05);
}

TEST_CASE("a wrong time stamp or a glitching pose does not spoil the rest of the log", "[estimation]") {
  const estimation_test::Recording rec = estimation_test::record_throw(estimation_test::WorldParams{}, 2);
  std::stringstream log;
  log << gs::estimation::kMocapLogHeader << '\n';
  std::size_t k = 0;
  for (const estimation_test::Frame& f : rec.frames) {
    write_row(log, f.t_s, "vehicle1", f.vehicle[0]);
    write_row(log, f.t_s, "vehicle2", f.vehicle[1]);
    write_row(log, f.t_s, "pole", f.pole);
    if (++k == 100) {
      // A pole row from a second later, and a pole pose 1 m off in the next frame.
      log << f.t_s + 1.0 << ",pole,1,2,3,1,0,0,0\n";
    }
    if (k == 150) log << f.t_s + 0.0025 << ",pole,5,5,5,1,0,0,0\n";
  }
  std::ostringstream out;
  std::ostringstream diag;
  gs::estimation::ReplayOptions options;
  options.catch_height_m = rec.catch_height;
  const gs::estimation::ReplaySummary s = gs::estimation::replay_mocap_log(log, out, diag, options);
  CHECK(s.ok);
  CHECK(s.reordered == 1);
  int reinitialised = 0;
  for (const auto& sw : s.switches) {
    reinitialised += sw.reason == gs::estimation::SwitchReason::reinitialised;
  }
  CHECK(reinitialised == 0);
  CHECK(s.health.pole.rejected == 2);
  // The estimate still finds the launch and the catch.
  bool free_seen = false;
  bool caught = false;
  for (const std::string& line : lines(out.str())) {
    free_seen |= line.find(",free,") != std::string::npos;
    caught |= free_seen && line.find(",on_vehicle2,") != std::string::npos;
  }
  CHECK(free_seen);
  CHECK(caught);
}
