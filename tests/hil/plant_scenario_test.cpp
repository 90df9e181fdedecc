// Scenarios and the recorder: the shipped scenario files, what a run records, the data
// generator's controllers, and `hil record`'s handling of bad input.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "hil/plant/recorder.hpp"
#include "hil/plant/scenario.hpp"
#include "hil/plant/scenario_runner.hpp"
#include "hil/plant/vehicle_controller.hpp"

using hil::Contact;
using hil::Scenario;
using hil::ScenarioResult;
using hil::Vec3;

namespace {

Scenario load(const std::string& name) {
  Scenario s;
  std::string error;
  INFO(error);
  REQUIRE(hil::load_scenario(hil::scenario_directory() + "/" + name, s, error));
  return s;
}

ScenarioResult run(const Scenario& s) {
  ScenarioResult r;
  std::string error;
  INFO(error);
  REQUIRE(hil::run_scenario(s, r, error));
  return r;
}

// A scratch directory for files the recorder writes.
std::string scratch() {
  const auto dir = std::filesystem::temp_directory_path() / "pa_hil_plant_scenario_test";
  std::filesystem::create_directories(dir);
  return dir.string();
}

std::string read(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

int record(const std::vector<std::string>& args, std::string& out, std::string& err) {
  std::ostringstream o;
  std::ostringstream e;
  const int code = hil::record_command(args, o, e);
  out = o.str();
  err = e.str();
  return code;
}

}  // namespace

TEST_CASE("free_flight_catch: the pole flies freely from its launch and lands on vehicle 2's plate") {
  const Scenario s = load("free_flight_catch.yaml");
  CHECK(s.name == "free_flight_catch");
  const ScenarioResult r = run(s);
  const double L = r.config.pole.half_length_m;
  REQUIRE(r.launch_t_s);
  REQUIRE(r.impact_t_s);
  REQUIRE(r.catch_position_m);
  CHECK(*r.launch_t_s == Approx(0.2));
  CHECK(r.impact_on == Contact::vehicle2);
  CHECK(r.impact_end == 1);  // the pole turned over in flight: its upper end lands
  INFO("impact at " << *r.impact_t_s << " s");
  CHECK(*r.impact_t_s > 1.0);
  CHECK(*r.impact_t_s < 1.5);

  // Truth at every plant tick.
  REQUIRE(r.pole_truth.size() == static_cast<std::size_t>(std::llround(s.duration_s / r.tick_s)));
  // Before the launch the pole moves unaccelerated with its launch velocity on the thrower's
  // plate; afterwards it flies free and touches nothing until the impact, exactly as a pole
  // launched alone in the same plant.
  const hil::PoleState launch = hil::launch_state(s);
  hil::Plant alone(r.config);
  alone.set_pole(launch);
  const auto launch_tick = static_cast<std::size_t>(std::llround(*r.launch_t_s / r.tick_s)) - 1;
  CHECK((r.pole_truth.at(launch_tick).position_m - launch.body.position_m).norm() < 1e-12);
  double worst_free_flight_m = 0.0;
  for (std::size_t k = 0; k < r.pole_truth.size(); ++k) {
    const hil::PoleTruthRow& row = r.pole_truth[k];
    if (row.t_s < *r.launch_t_s - 1e-9) {
      CHECK(row.velocity_mps.isApprox(launch.body.velocity_mps, 1e-12));
      CHECK(row.contact == Contact::vehicle1);
    }
    if (row.t_s > *r.launch_t_s + 1e-9 && row.t_s < *r.impact_t_s - 1e-9) {
      CHECK(row.contact == Contact::none);
      alone.step(r.tick_s, {}, {});
      worst_free_flight_m =
          std::max(worst_free_flight_m, (alone.pole().body.position_m - row.position_m).norm());
    }
  }
  // (The two plants choose different integration steps: the parked vehicles of `alone` keep it
  // on the short contact step.)
  CHECK(worst_free_flight_m < 1e-8);
  // At the impact, the landing end is on the plate, near the catch point.
  const auto at_impact = static_cast<std::size_t>(std::ceil(*r.impact_t_s / r.tick_s - 1e-9)) - 1;
  const hil::PoleTruthRow& hit = r.pole_truth.at(at_impact);
  CHECK(hit.contact == Contact::vehicle2);
  const Vec3 end = hit.position_m + L * hit.axis;
  const Vec3 plate = *r.catch_position_m + Vec3(0, 0, r.config.vehicle.plate_height_m);
  CHECK((end - plate).head<2>().norm() < r.config.vehicle.plate_radius_m);
  CHECK(end.z() == Approx(plate.z()).margin(0.01));

  // Motion capture: all three bodies in every frame, 200 Hz, delivered after the latency, and
  // the pole's pose is the truth at capture time plus millimetre noise.
  // Every frame captured at least the latency before the end has been delivered.
  const auto delivered_frames = static_cast<std::size_t>((s.duration_s - r.config.mocap.latency_s) / 0.005);
  REQUIRE(r.mocap.size() >= 3 * delivered_frames);
  std::size_t pole_rows = 0;
  for (std::size_t i = 0; i < r.mocap.size(); ++i) {
    const hil::MocapRow& m = r.mocap[i];
    CHECK(static_cast<int>(m.body) == static_cast<int>(i % 3));
    CHECK(m.capture_t_s == Approx(0.005 * static_cast<double>(i / 3)).margin(1e-9));
    CHECK(m.t_s == Approx(m.capture_t_s + r.config.mocap.latency_s).margin(1e-9));
    CHECK(m.attitude.w() >= 0.0);
    if (m.body != hil::Body::pole || m.capture_t_s < r.tick_s) continue;
    const auto k = static_cast<std::size_t>(std::llround(m.capture_t_s / r.tick_s)) - 1;
    const hil::PoleTruthRow& t = r.pole_truth.at(k);
    CHECK((m.position_m - t.position_m).norm() < 0.006);
    CHECK((m.attitude * Vec3::UnitZ() - t.axis).norm() < 0.006);
    ++pole_rows;
  }
  CHECK(pole_rows >= delivered_frames - 1);  // the first frame, at t = 0, precedes any truth row
  // The IMUs ran at 1 kHz.
  CHECK(r.imu[1].size() == r.pole_truth.size());
}

TEST_CASE("balanced_hover: the pole stays balanced on vehicle 1, which holds its place") {
  const Scenario s = load("balanced_hover.yaml");
  const ScenarioResult r = run(s);
  CHECK_FALSE(r.impact_t_s);
  double lowest_nz = 1.0;
  for (const hil::PoleTruthRow& row : r.pole_truth) {
    CHECK(row.contact == Contact::vehicle1);
    lowest_nz = std::min(lowest_nz, row.axis.z());
  }
  CHECK(lowest_nz > std::cos(0.08));
  double worst = 0.0;
  for (const hil::VehicleTruthRow& v : r.vehicle_truth) {
    if (v.vehicle == pa::kVehicle1)
      worst = std::max(worst, (v.state.body.position_m - s.vehicle[0].position_m).norm());
  }
  INFO("largest excursion of vehicle 1: " << worst << " m");
  CHECK(worst < 0.15);
  // Settled: still and upright at the end.
  CHECK(r.pole_truth.back().axis.z() > std::cos(0.005));
  CHECK(r.pole_truth.back().rate_radps.norm() < 0.01);
}

TEST_CASE("every shipped scenario loads and runs; in throw the uncaught pole ends on the floor") {
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(hil::scenario_directory())) {
    if (entry.path().extension() != ".yaml") continue;
    ++count;
    INFO(entry.path().string());
    Scenario s;
    std::string error;
    REQUIRE(hil::load_scenario(entry.path().string(), s, error));
    CHECK(entry.path().stem().string() == s.name);
    const ScenarioResult r = run(s);
    CHECK_FALSE(r.mocap.empty());
    if (s.name == "throw") {
      CHECK_FALSE(r.impact_t_s);  // no plate was hit
      CHECK(r.pole_truth.back().contact == Contact::floor);
    }
  }
  CHECK(count >= 3);
}

TEST_CASE("a scenario run is reproducible for a seed; randomised runs differ between seeds") {
  Scenario s = load("free_flight_catch.yaml");
  s.duration_s = 1.5;
  const ScenarioResult a = run(s);
  const ScenarioResult b = run(s);
  REQUIRE(a.mocap.size() == b.mocap.size());
  for (std::size_t i = 0; i < a.mocap.size(); ++i) CHECK(a.mocap[i].position_m == b.mocap[i].position_m);
  CHECK(*a.impact_t_s == *b.impact_t_s);

  s.randomise = true;
  s.seed = 1;
  const ScenarioResult r1 = run(s);
  s.seed = 2;
  const ScenarioResult r2 = run(s);
  CHECK(r1.config.mocap.latency_s != r2.config.mocap.latency_s);
  // Different drag, different flight: the catcher is put at a different place.
  CHECK((*r1.catch_position_m - *r2.catch_position_m).norm() > 1e-4);
}

TEST_CASE("the data generator's controller brings a displaced vehicle back to its setpoint") {
  hil::PlantConfig c;
  c.vehicle.motor_gain[0] = {1.04, 0.97, 1.0, 1.02};  // the controller does not know these
  hil::Plant plant(c);
  plant.set_vehicle(pa::kVehicle1, plant.hovering_vehicle(Vec3(0.5, -0.4, 1.2), 0.5));
  hil::VehicleController controller(hil::VehicleConfig{}, c.gravity_mps2);
  hil::VehicleSetpoint sp;
  sp.position_m = Vec3(0, 0, 1.5);
  sp.yaw_rad = 0.0;
  for (int k = 0; k < 8000; ++k) {
    plant.step(0.001, controller.update(plant.vehicle(pa::kVehicle1), sp, 0.001), hil::MotorCommands{});
  }
  const hil::RigidBodyState& b = plant.vehicle(pa::kVehicle1).body;
  CHECK((b.position_m - sp.position_m).norm() < 0.02);
  CHECK(b.velocity_mps.norm() < 0.01);
  const Vec3 nose = b.attitude * Vec3::UnitX();
  CHECK(std::atan2(nose.y(), nose.x()) == Approx(0.0).margin(0.02));
}

TEST_CASE("bad scenario files are reported with file and line") {
  struct Case {
    const char* text;
    const char* message;
  };
  const Case cases[] = {
      {"name: x\nvehicle1_mode: hover\n",
       "bad.yaml:2: 'vehicle1_mode' must be parked, hold, balance or thrower, got 'hover'"},
      {"name: x\nduration_s: -1\n", "bad.yaml:2: 'duration_s' = -1 is outside"},
      {"name: x\npole_velocity_mps: [1, 2]\n", "bad.yaml:2: 'pole_velocity_mps' needs three numbers"},
      {"name: x\nflux: 3\n", "bad.yaml:2: unknown scenario key 'flux'"},
      {"name: x\n\nplant:\n  pole_mass_kg: -3\n", "bad.yaml:4: 'pole_mass_kg' = -3 is outside"},
      {"name: x\nplant:\n  warp: 1\n", "bad.yaml:3: unknown plant parameter 'warp'"},
      {"name: x\nplant_config: missing.yaml\n", "bad.yaml:2: plant_config: "},
      {"name: x\nseed: -4\n", "bad.yaml:2: 'seed' needs a non-negative integer"},
      {"name: x\nvehicle2_mode: hold\n",
       "bad.yaml: 'vehicle2_position_m' is required for a vehicle that flies"},
      {"name: x\npole_start: balanced\nvehicle1_mode: parked\n",
       "bad.yaml: the pole is balanced on vehicle1, which is parked"},
      {"vehicle1_mode: parked\n", "bad.yaml: 'name' is required"},
      {"name: x\nname: y\n", "bad.yaml:2: 'name' is given twice (first on line 1)"},
      {"name: x\nvehicle2_mode: hold\nvehicle2_position_m: auto\npole_start: balanced\nvehicle1_mode: balance\n"
       "vehicle1_position_m: [0, 0, 1]\n",
       "bad.yaml: 'vehicle2_position_m: auto' needs a flying vehicle and pole_start: launch"},
      {"name: x\nvehicle1_mode: thrower\nvehicle1_position_m: [0, 0, 1]\npole_start: balanced\n",
       "bad.yaml: vehicle1_mode: thrower needs pole_start: launch"},
      {"name: x\nvehicle2_after_catch: thrower\n",
       "bad.yaml:2: 'vehicle2_after_catch' must be hold or balance"},
      {"name: x\nduration_s: soon\n", "bad.yaml:2: 'duration_s' needs a finite number, got 'soon'"},
      {"name: x\nplant: 3\n", "bad.yaml:2: expected a map"},
      {"name: x\npole_position_m: [1, 2, 3\n", "bad.yaml:3: "},  // YAML syntax: the list is never closed
      {"name: x\nrandomise: maybe\n", "bad.yaml:2: 'randomise' needs true or false"},
  };
  for (const Case& c : cases) {
    INFO(c.text);
    Scenario s;
    std::string error;
    CHECK_FALSE(hil::parse_scenario(c.text, "bad.yaml", hil::scenario_directory(), s, error));
    INFO(error);
    CHECK(error.rfind(c.message, 0) == 0);
  }
}

TEST_CASE("a catcher cannot be placed for a pole that never comes down to the catch height") {
  Scenario s = load("free_flight_catch.yaml");
  s.catch_height_m = 50.0;
  ScenarioResult r;
  std::string error;
  CHECK_FALSE(hil::run_scenario(s, r, error));
  CHECK(error.find("never comes down through catch_height_m") != std::string::npos);
}

TEST_CASE("hil record writes the motion-capture log and the truth, and prints the true times") {
  const std::string dir = scratch();
  const std::string mocap = dir + "/record_mocap.csv";
  const std::string truth = dir + "/record_truth.csv";
  std::string out;
  std::string err;
  const int code = record({"--scenario", hil::scenario_directory() + "/free_flight_catch.yaml", "--out",
                           mocap, "--truth", truth, "--stamp", "capture"},
                          out, err);
  INFO(err);
  REQUIRE(code == 0);
  CHECK(out.find("launch_t_s = 0.2000") != std::string::npos);
  CHECK(out.find("impact_t_s = 1.") != std::string::npos);
  CHECK(out.find("on vehicle2") != std::string::npos);
  const std::string log = read(mocap);
  CHECK(log.rfind("t,body,x,y,z,qw,qx,qy,qz\n0.000000,vehicle1,", 0) == 0);
  CHECK(log.find("\n0.000000,pole,") != std::string::npos);
  const std::string t = read(truth);
  CHECK(t.rfind("t,px,py,pz,vx,vy,vz,nx,ny,nz,wx,wy,wz,contact\n0.001000,", 0) == 0);
  CHECK(t.find(",vehicle2\n") != std::string::npos);
  std::remove(mocap.c_str());
  std::remove(truth.c_str());
}

TEST_CASE("hil record rejects bad arguments with exit code 2 and a message") {
  const std::string scenario = hil::scenario_directory() + "/free_flight_catch.yaml";
  struct Case {
    std::vector<std::string> args;
    const char* message;
  };
  const Case cases[] = {
      {{}, "--scenario is required"},
      {{"--scenario", scenario}, "--out is required"},
      {{"--scenario", scenario, "--out"}, "--out needs a value"},
      {{"--bogus"}, "unknown argument '--bogus'"},
      {{"--scenario", scenario, "--out", "x.csv", "--seed", "many"}, "--seed needs a non-negative integer"},
      {{"--scenario", scenario, "--out", "x.csv", "--stamp", "arrival"},
       "--stamp must be delivery or capture"},
      {{"--scenario", "/nonexistent.yaml", "--out", "x.csv"}, "/nonexistent.yaml: cannot read the file"},
  };
  for (const Case& c : cases) {
    std::string out;
    std::string err;
    INFO(c.message);
    CHECK(record(c.args, out, err) == 2);
    CHECK(err.find(c.message) != std::string::npos);
  }
  // A bad scenario file: its name and line.
  const std::string bad = scratch() + "/bad.yaml";
  {
    std::ofstream f(bad);
    f << "name: bad\n# ok\nduration_s: soon\n";
  }
  std::string out;
  std::string err;
  CHECK(record({"--scenario", bad, "--out", "x.csv"}, out, err) == 2);
  CHECK(err.find(bad + ":3: 'duration_s' needs a finite number") != std::string::npos);
  std::remove(bad.c_str());
  // An output that cannot be written.
  CHECK(record({"--scenario", scenario, "--out", "/nonexistent/dir/x.csv"}, out, err) == 1);
  CHECK(err.find("cannot write '/nonexistent/dir/x.csv'") != std::string::npos);
  CHECK(record({"--help"}, out, err) == 0);
  CHECK(out.find("usage: hil record") != std::string::npos);
}
