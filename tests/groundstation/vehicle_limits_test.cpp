// Input limits (1), (2) and their documented YAML file.
#include "groundstation/model/vehicle_limits.hpp"

#include <catch2/catch.hpp>
#include <string>

namespace {

using gs::model::parse_vehicle_limits;

constexpr const char* kValid = "# comment\n"
                               "a_q_min_mps2: 1.0\n"
                               "\n"
                               "a_q_max_mps2:   20   # trailing comment\n"
                               "omega_max_radps: 10.0\n";

std::string replace_line(std::string text, const std::string& from, const std::string& to) {
  text.replace(text.find(from), from.size(), to);
  return text;
}

}  // namespace

TEST_CASE("the repository's limits file loads and admits the paper's manoeuvres", "[limits]") {
  const std::string path = std::string(PA_SOURCE_DIR) + "/" + gs::model::kVehicleLimitsRelativePath;
  const gs::model::VehicleLimitsLoad load = gs::model::load_vehicle_limits(path);
  INFO(load.error);
  REQUIRE(load.ok);
  const gs::model::VehicleLimits& lim = load.limits;
  // Eq. (1) holds and the vehicle can hover.
  CHECK(lim.a_q_min_mps2 > 0.0);
  CHECK(lim.a_q_min_mps2 < pa::kGravity_mps2);
  CHECK(lim.a_q_max_mps2 > pa::kGravity_mps2);
  // The Fig. 5 launch input (a_q, Omega_y) = (4.48, 2.5) and the Fig. 7 catch thrust
  // (g + a_max = 9.81 + 4.19 m/s^2) are feasible.
  gs::model::VehicleInput launch;
  launch.a_q_mps2 = 4.48;
  launch.omega_radps = Eigen::Vector3d(0.0, 2.5, 0.0);
  CHECK(gs::model::input_within_limits(launch, lim));
  gs::model::VehicleInput catch_thrust;
  catch_thrust.a_q_mps2 = pa::kGravity_mps2 + 4.19;
  CHECK(gs::model::input_within_limits(catch_thrust, lim));
}

TEST_CASE("a well-formed file with comments and blank lines parses", "[limits]") {
  const auto load = parse_vehicle_limits(kValid, "test.yaml");
  REQUIRE(load.ok);
  CHECK(load.limits.a_q_min_mps2 == 1.0);
  CHECK(load.limits.a_q_max_mps2 == 20.0);
  CHECK(load.limits.omega_max_radps == 10.0);
}

TEST_CASE("malformed limits files are rejected with file and line", "[limits]") {
  const std::string valid = kValid;
  struct Case {
    std::string text;
    std::string expect;
  };
  const Case cases[] = {
      {replace_line(valid, "a_q_min_mps2: 1.0", "a_q_min_mps2 1.0"), "test.yaml:"},      // YAML syntax
      {replace_line(valid, "a_q_min_mps2: 1.0", "a_q_min_mps2: [1.0"), "test.yaml:4:"},  // YAML syntax
      {replace_line(valid, "a_q_min_mps2: 1.0", "a_q_minimum: 1.0"), "test.yaml:2: unknown key"},
      {valid + "a_q_min_mps2: 2.0\n", "test.yaml:6: 'a_q_min_mps2' is given twice (first on line 2)"},
      {replace_line(valid, ": 1.0", ": one"), "test.yaml:2: value"},
      {replace_line(valid, ": 1.0", ": 1.0 m/s^2"), "test.yaml:2: value"},
      {replace_line(valid, ": 1.0", ": .nan"), "test.yaml:2: value"},
      {replace_line(valid, ": 1.0", ": .inf"), "test.yaml:2: value"},
      {replace_line(valid, ": 1.0", ":"), "test.yaml:2: value"},
      {replace_line(valid, "omega_max_radps: 10.0\n", ""), "test.yaml: missing key `omega_max_radps`"},
      {replace_line(valid, ": 1.0", ": 0.0"), "test.yaml:2: a_q_min_mps2 must be > 0"},
      {replace_line(valid, ": 1.0", ": 25.0"), "test.yaml:4: a_q_max_mps2 must exceed"},
      {replace_line(valid, ": 10.0", ": -1.0"), "test.yaml:5: omega_max_radps must be > 0"},
      {"", "test.yaml: missing key"},
      {"- 1.0\n- 20.0\n", "test.yaml:1: expected a map"},
  };
  for (const Case& c : cases) {
    INFO(c.text);
    const auto load = parse_vehicle_limits(c.text, "test.yaml");
    INFO(load.error);
    CHECK_FALSE(load.ok);
    CHECK(load.error.find(c.expect) != std::string::npos);
  }
}

TEST_CASE("a missing limits file is an error, not an exception", "[limits]") {
  const auto load = gs::model::load_vehicle_limits("/nonexistent/dir/limits.yaml");
  CHECK_FALSE(load.ok);
  CHECK(load.error.find("/nonexistent/dir/limits.yaml") != std::string::npos);
}

TEST_CASE("eq. (1), (2): limit check and saturation", "[limits]") {
  const gs::model::VehicleLimits lim{1.0, 20.0, 10.0};
  gs::model::VehicleInput u;
  u.a_q_mps2 = 20.0;
  u.omega_radps = Eigen::Vector3d(-10.0, 10.0, 0.0);
  CHECK(gs::model::input_within_limits(u, lim));
  u.a_q_mps2 = 20.5;
  CHECK_FALSE(gs::model::input_within_limits(u, lim));
  u.a_q_mps2 = 0.5;
  CHECK_FALSE(gs::model::input_within_limits(u, lim));
  u.a_q_mps2 = 5.0;
  u.omega_radps.z() = -10.1;
  CHECK_FALSE(gs::model::input_within_limits(u, lim));
  u.omega_radps.z() = std::nan("");
  CHECK_FALSE(gs::model::input_within_limits(u, lim));

  gs::model::VehicleInput wild;
  wild.a_q_mps2 = 30.0;
  wild.omega_radps = Eigen::Vector3d(-12.0, 3.0, 11.0);
  const gs::model::VehicleInput sat = gs::model::saturate_input(wild, lim);
  CHECK(sat.a_q_mps2 == 20.0);
  CHECK(sat.omega_radps == Eigen::Vector3d(-10.0, 3.0, 10.0));
  CHECK(gs::model::input_within_limits(sat, lim));
  wild.a_q_mps2 = 0.0;
  CHECK(gs::model::saturate_input(wild, lim).a_q_mps2 == 1.0);
}
