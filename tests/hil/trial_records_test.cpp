// The trials' records through the workers' pipe and into the CSV files (hil/trials/record_schema.hpp):
// every field of an attempt's result and of a cut survives the report exactly (each filled with a
// value of its own, so that a field the codec dropped or swapped would come back different), a
// report that does not read is refused, and the CSV files keep their columns and formats.
#include <catch2/catch.hpp>

#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

#include "hil/trials/attempt_result.hpp"
#include "hil/trials/campaign.hpp"
#include "hil/trials/cuts.hpp"

namespace {

using hil::trials::AttemptResult;

// Every field distinct from its default and from every other field.
AttemptResult distinct_result() {
  AttemptResult r;
  r.throw_number = 7;
  r.outcome = gs::adaptation::ThrowOutcome::aborted_out_of_reach;  // not the default, aborted
  r.flight_s = 1.0123456789012345;
  r.catch_height_m = 2.0123456789012345;
  r.catch_x_m = 3.6000000000000001;
  r.catch_y_m = -0.010000000000000002;
  r.travel_m = 0.070000000000000007;
  r.energy_error_J = -0.00312;
  r.impact = true;
  r.abort_reason = "out_of_reach";
  r.planned_height_m = 1.9876543210987654;
  r.optimal_height_m = 2.1234567890123456;
  r.vehicle_crashed = true;
  r.predicted_target_miss_m = 0.0123;
  r.target_miss_m = 0.0456;
  r.thrower = 2;
  r.innovation_switches = 11;
  return r;
}

void check_same(const AttemptResult& a, const AttemptResult& b) {
  CHECK(a.throw_number == b.throw_number);
  CHECK(a.outcome == b.outcome);
  CHECK(a.flight_s == b.flight_s);
  CHECK(a.catch_height_m == b.catch_height_m);
  CHECK(a.catch_x_m == b.catch_x_m);
  CHECK(a.catch_y_m == b.catch_y_m);
  CHECK(a.travel_m == b.travel_m);
  CHECK(a.energy_error_J == b.energy_error_J);
  CHECK(a.impact == b.impact);
  CHECK(a.abort_reason == b.abort_reason);
  CHECK(a.planned_height_m == b.planned_height_m);
  CHECK(a.optimal_height_m == b.optimal_height_m);
  CHECK(a.vehicle_crashed == b.vehicle_crashed);
  CHECK(a.predicted_target_miss_m == b.predicted_target_miss_m);
  CHECK(a.target_miss_m == b.target_miss_m);
  CHECK(a.thrower == b.thrower);
  CHECK(a.innovation_switches == b.innovation_switches);
}

hil::trials::CutResult distinct_cut() {
  hil::trials::CutResult r;
  r.cut = 12;
  r.mission = 3;
  r.mission_seed = 1000000000007ULL;
  r.phase = hil::trials::CutPhase::catching;
  r.t_cut_s = 13.0123456789012345;
  r.min_separation_m = 1.2345678901234567;
  r.run_s = 7.123;
  for (std::size_t i = 0; i < 2; ++i) {
    hil::trials::VehicleCut& c = r.vehicles[i];
    const double k = 1.0 + static_cast<double>(i);  // the two vehicles differ too
    c.mode_at_cut = i == 0 ? "flying" : "taking_off";
    c.height_m = 2.1 * k;
    c.tilt_at_cut_rad = 0.11 * k;
    c.failsafe_after_s = 0.021 * k;
    c.levelled_after_s = 0.31 * k;
    c.max_tilt_rad = 0.41 * k;
    c.touchdown_after_s = 5.1 * k;
    c.touchdown_speed_mps = 0.4321 * k;
    c.touchdown_tilt_rad = 0.061 * k;
    c.drift_m = 0.71 * k;
    c.final_mode = i == 0 ? "landed" : "killed";
    c.landed = i == 0;
    c.motors_off = true;
    c.crashed = i == 1;
    c.failure = i == 0 ? "" : "crashed+not_landed";
  }
  return r;
}

void check_same(const hil::trials::CutResult& a, const hil::trials::CutResult& b) {
  CHECK(a.cut == b.cut);
  CHECK(a.mission == b.mission);
  CHECK(a.mission_seed == b.mission_seed);
  CHECK(a.phase == b.phase);
  CHECK(a.t_cut_s == b.t_cut_s);
  CHECK(a.min_separation_m == b.min_separation_m);
  CHECK(a.run_s == b.run_s);
  for (std::size_t i = 0; i < 2; ++i) {
    INFO("vehicle slot " << i);
    const hil::trials::VehicleCut &x = a.vehicles[i], &y = b.vehicles[i];
    CHECK(x.mode_at_cut == y.mode_at_cut);
    CHECK(x.height_m == y.height_m);
    CHECK(x.tilt_at_cut_rad == y.tilt_at_cut_rad);
    CHECK(x.failsafe_after_s == y.failsafe_after_s);
    CHECK(x.levelled_after_s == y.levelled_after_s);
    CHECK(x.max_tilt_rad == y.max_tilt_rad);
    CHECK(x.touchdown_after_s == y.touchdown_after_s);
    CHECK(x.touchdown_speed_mps == y.touchdown_speed_mps);
    CHECK(x.touchdown_tilt_rad == y.touchdown_tilt_rad);
    CHECK(x.drift_m == y.drift_m);
    CHECK(x.final_mode == y.final_mode);
    CHECK(x.landed == y.landed);
    CHECK(x.motors_off == y.motors_off);
    CHECK(x.crashed == y.crashed);
    CHECK(x.failure == y.failure);
  }
}

}  // namespace

TEST_CASE("a worker's report carries every field of an attempt's result exactly", "[hil][trials]") {
  const AttemptResult r = distinct_result();
  AttemptResult back;  // defaults: every field differs from r's
  REQUIRE(hil::trials::decode_result(hil::trials::encode_result(r), back));
  check_same(back, r);
  // Every field is read from its own place: each field of the schema decoded from a report of
  // the defaults but for that one field brings back r's value there and the default elsewhere.
  const auto& schema = hil::trials::attempt_schema();
  const std::vector<std::string> defaults =
      hil::trials::split(hil::trials::encode_result(AttemptResult{}), '\t');
  const std::vector<std::string> mine = hil::trials::split(hil::trials::encode_result(r), '\t');
  REQUIRE(defaults.size() == schema.size());
  REQUIRE(mine.size() == schema.size());
  CHECK(schema.size() == 17);  // a field added to AttemptResult belongs in its schema
  for (std::size_t i = 0; i < schema.size(); ++i) {
    INFO(schema[i].name);
    CHECK(mine[i] != defaults[i]);
  }
}

TEST_CASE("an attempt's report with an empty last field or unreadable fields", "[hil][trials]") {
  AttemptResult r = distinct_result();
  r.target_miss_m = -1.0;
  r.abort_reason.clear();
  AttemptResult back;
  REQUIRE(hil::trials::decode_result(hil::trials::encode_result(r), back));
  CHECK(back.abort_reason.empty());
  CHECK_FALSE(hil::trials::decode_result("caught\t1.0\tnot a number", back));
  CHECK_FALSE(hil::trials::decode_result("", back));
  std::string line = hil::trials::encode_result(r);
  CHECK_FALSE(hil::trials::decode_result(line + "\t1", back));  // one field too many
  line.replace(line.find("\t1\t"), 3, "\tyes\t");               // a flag that is not 0 or 1
  CHECK_FALSE(hil::trials::decode_result(line, back));
  line = hil::trials::encode_result(r);
  line.replace(line.find("\taborted_out_of_reach\t"), 22, "\tpractice\t");  // no outcome's name
  CHECK_FALSE(hil::trials::decode_result(line, back));
  // Fields that decode but hold what no attempt gives: a thrower outside the act, negative switches.
  const auto& schema = hil::trials::attempt_schema();
  const auto index_of = [&](const std::string& name) {
    const auto it = std::find_if(schema.begin(), schema.end(), [&](const auto& f) { return f.name == name; });
    REQUIRE(it != schema.end());
    return static_cast<std::size_t>(it - schema.begin());
  };
  const std::size_t thrower = index_of("thrower"), switches = index_of("innovation_switches");
  const auto with = [&](const std::string& thrower_text, const std::string& switches_text) {
    std::vector<std::string> fields = hil::trials::split(hil::trials::encode_result(r), '\t');
    fields[thrower] = thrower_text;
    fields[switches] = switches_text;
    std::string joined = fields.front();
    for (std::size_t i = 1; i < fields.size(); ++i) joined += "\t" + fields[i];
    return joined;
  };
  CHECK(hil::trials::decode_result(with("1", "0"), back));
  CHECK_FALSE(hil::trials::decode_result(with("7", "0"), back));
  CHECK_FALSE(hil::trials::decode_result(with("0", "0"), back));
  CHECK_FALSE(hil::trials::decode_result(with("2", "-5"), back));
}

TEST_CASE("a worker's cut report carries every field of its cuts exactly", "[hil][trials][cuts]") {
  hil::trials::CutResult other = distinct_cut();
  other.cut = 13;
  other.phase = hil::trials::CutPhase::after_catch;
  std::vector<hil::trials::CutResult> back;
  REQUIRE(hil::trials::decode_cuts(hil::trials::encode_cuts({distinct_cut(), other}), back));
  REQUIRE(back.size() == 2);
  check_same(back[0], distinct_cut());
  check_same(back[1], other);
  CHECK(hil::trials::cut_schema().size() == 7 + 2 * 15);
  REQUIRE(hil::trials::decode_cuts("", back));
  CHECK(back.empty());
  CHECK_FALSE(hil::trials::decode_cuts("1\t2\tnot a number", back));
  std::string line = hil::trials::encode_cuts({distinct_cut()});
  line.replace(line.find("\t3\t1000000000007\t3\t"), 19, "\t3\t1000000000007\t9\t");  // no phase 9
  CHECK_FALSE(hil::trials::decode_cuts(line, back));
}

TEST_CASE("the CSV files keep their columns and formats", "[hil][trials]") {
  std::ostringstream fly;
  hil::trials::write_csv(fly, hil::trials::fly_throws_columns(),
                         std::vector<AttemptResult>{distinct_result()});
  CHECK(fly.str() ==
        "throw,outcome,flight_s,catch_height_m,catch_x_m,catch_y_m,travel_m,energy_error_J,abort_reason,"
        "planned_height_m,optimal_height_m\n"
        "7,aborted_out_of_reach,1.0123,2.0123,3.6000,-0.0100,0.0700,-0.00312,out_of_reach,1.9877,2.1235\n");

  hil::trials::CampaignAttempt a;
  a.result = distinct_result();
  a.seed = 1000004;
  const auto columns = hil::trials::campaign_throws_columns(a.plant);
  const std::string header = hil::trials::csv_header(columns);
  CHECK(
      header.rfind(
          "throw,outcome,flight_s,catch_height_m,catch_x_m,catch_y_m,travel_m,energy_error_J,"
          "abort_reason,vehicle_crashed,planned_height_m,optimal_height_m,thrower,innovation_switches,seed,",
          0) == 0);
  CHECK(
      hil::trials::csv_row(columns, a)
          .rfind(
              "7,aborted_out_of_reach,1.0123,2.0123,3.6000,-0.0100,0.0700,-0.00312,out_of_reach,1,1.9877,2.1235,2,"
              "11,1000004,",
              0) == 0);

  const hil::trials::CutResult cut = distinct_cut();
  const auto cut_columns = hil::trials::cuts_csv_columns();
  CHECK(hil::trials::csv_header(cut_columns) ==
        "cut,mission,mission_seed,phase,t_cut_s,vehicle,mode_at_cut,height_m,tilt_at_cut_deg,"
        "failsafe_after_s,levelled_after_s,max_tilt_deg,touchdown_after_s,touchdown_speed_mps,"
        "touchdown_tilt_deg,drift_m,min_separation_m,final_mode,landed,motors_off,crashed,failure");
  CHECK(hil::trials::csv_row(cut_columns, hil::trials::CutRow{&cut, pa::kVehicle2}) ==
        "12,3,1000000000007,catch,13.012,2,taking_off,4.200,12.61,0.042,0.620,46.98,10.200,0.8642,6.99,1.420,"
        "1.235,killed,0,1,1,crashed+not_landed");
}
