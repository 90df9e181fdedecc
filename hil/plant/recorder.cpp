#include "hil/plant/recorder.hpp"

#include <cstdio>
#include <exception>
#include <fstream>
#include <optional>

#include "pa/command_line.hpp"

namespace hil {

namespace {

std::string format(const char* fmt, auto... values) {
  char buf[512];
  std::snprintf(buf, sizeof buf, fmt, values...);
  return buf;
}

}  // namespace

void write_mocap_csv(std::ostream& out, const std::vector<MocapRow>& rows, MocapStamp stamp) {
  out << "t,body,x,y,z,qw,qx,qy,qz\n";
  for (const MocapRow& r : rows) {
    const double t = stamp == MocapStamp::delivery ? r.t_s : r.capture_t_s;
    const std::string_view name = body_name(r.body);
    out << format("%.6f,%.*s,%.6f,%.6f,%.6f,%.9f,%.9f,%.9f,%.9f\n", t, static_cast<int>(name.size()),
                  name.data(), r.position_m.x(), r.position_m.y(), r.position_m.z(), r.attitude.w(),
                  r.attitude.x(), r.attitude.y(), r.attitude.z());
  }
}

void write_pole_truth_csv(std::ostream& out, const std::vector<PoleTruthRow>& rows) {
  out << "t,px,py,pz,vx,vy,vz,nx,ny,nz,wx,wy,wz,contact\n";
  for (const PoleTruthRow& r : rows) {
    const std::string_view contact = contact_name(r.contact);
    out << format("%.6f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.*s\n", r.t_s,
                  r.position_m.x(), r.position_m.y(), r.position_m.z(), r.velocity_mps.x(),
                  r.velocity_mps.y(), r.velocity_mps.z(), r.axis.x(), r.axis.y(), r.axis.z(),
                  r.rate_radps.x(), r.rate_radps.y(), r.rate_radps.z(), static_cast<int>(contact.size()),
                  contact.data());
  }
}

void write_vehicle_truth_header(std::ostream& out) {
  out << "t,vehicle,x,y,z,vx,vy,vz,qw,qx,qy,qz,wx,wy,wz,f0,f1,f2,f3\n";
}

void write_vehicle_truth_row(std::ostream& out, const VehicleTruthRow& r) {
  const RigidBodyState& b = r.state.body;
  const Quat q = b.attitude.w() < 0.0
                     ? Quat(-b.attitude.w(), -b.attitude.x(), -b.attitude.y(), -b.attitude.z())
                     : b.attitude;
  const auto& f = r.state.motor_thrust_N;
  out << format(
      "%.6f,vehicle%d,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.6f,%.6f,%.6f,%.6f\n",
      r.t_s, r.vehicle.node(), b.position_m.x(), b.position_m.y(), b.position_m.z(), b.velocity_mps.x(),
      b.velocity_mps.y(), b.velocity_mps.z(), q.w(), q.x(), q.y(), q.z(), b.rate_body_radps.x(),
      b.rate_body_radps.y(), b.rate_body_radps.z(), f[0], f[1], f[2], f[3]);
}

void write_vehicle_truth_csv(std::ostream& out, const std::vector<VehicleTruthRow>& rows) {
  write_vehicle_truth_header(out);
  for (const VehicleTruthRow& r : rows) write_vehicle_truth_row(out, r);
}

namespace {

struct RecordArguments {
  std::string scenario_path;
  std::string out_path;
  std::string truth_path;
  std::string vehicle_truth_path;
  std::optional<std::uint64_t> seed;
  bool randomise = false;
  std::string stamp = "delivery";
};

// The command line of `hil record`, also the source of its help.
void define_record_arguments(CLI::App& app, RecordArguments& a) {
  pa::cli::describe(
      app,
      "usage: hil record --scenario FILE --out FILE.csv [--truth FILE.csv] [--vehicle-truth FILE.csv]\n"
      "                  [--seed N] [--randomise] [--stamp delivery|capture]",
      "Runs a scenario (hil/config/scenarios/*.yaml) on the truth plant and writes the\n"
      "motion-capture log (t,body,x,y,z,qw,qx,qy,qz), optionally the true pole state\n"
      "(t,px,py,pz,vx,vy,vz,nx,ny,nz,wx,wy,wz,contact) and the true vehicle states.");
  app.add_option("--scenario", a.scenario_path, "the scenario file")->type_name("FILE")->required();
  app.add_option("--out", a.out_path, "the motion-capture CSV")->type_name("FILE.csv")->required();
  app.add_option("--truth", a.truth_path, "the true pole state as CSV")->type_name("FILE.csv");
  app.add_option("--vehicle-truth", a.vehicle_truth_path, "the true vehicle states as CSV")
      ->type_name("FILE.csv");
  app.add_option("--seed", a.seed, "overrides the scenario's seed (noise, IMU bias, randomisation)")
      ->type_name("N")
      ->check(pa::cli::count(0, UINT64_MAX, "needs a non-negative integer"));
  app.add_flag("--randomise", a.randomise, "draws the uncertain plant parameters from the seed");
  app.add_option("--stamp", a.stamp,
                 "delivery (default): t is when the frame reached the ground station;\n"
                 "capture: t is when the poses were true")
      ->type_name("")
      ->check(pa::cli::one_of({"delivery", "capture"}, "must be delivery or capture"));
}

}  // namespace

void print_record_usage(std::ostream& out) {
  CLI::App app("", "hil record");
  RecordArguments a;
  define_record_arguments(app, a);
  out << app.help();
}

namespace {

bool write_file(const std::string& path, const auto& writer, std::ostream& err) {
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  if (!file) {
    err << "hil record: cannot write '" << path << "'\n";
    return false;
  }
  writer(file);
  file.flush();
  if (!file) {
    err << "hil record: writing '" << path << "' failed\n";
    return false;
  }
  return true;
}

int record(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  CLI::App app("", "hil record");
  RecordArguments a;
  define_record_arguments(app, a);
  if (const std::optional<int> code = pa::cli::parse(app, args, out, err)) return *code;
  const std::string& scenario_path = a.scenario_path;
  const std::string& out_path = a.out_path;
  const std::string& truth_path = a.truth_path;
  const std::string& vehicle_truth_path = a.vehicle_truth_path;
  const std::optional<std::uint64_t>& seed = a.seed;
  const bool randomise = a.randomise;
  const MocapStamp stamp = a.stamp == "capture" ? MocapStamp::capture : MocapStamp::delivery;

  Scenario scenario;
  std::string error;
  if (!load_scenario(scenario_path, scenario, error)) {
    err << "hil record: " << error << "\n";
    return 2;
  }
  if (seed) scenario.seed = *seed;
  if (randomise) scenario.randomise = true;

  ScenarioResult result;
  if (!run_scenario(scenario, result, error)) {
    err << "hil record: " << error << "\n";
    return 2;
  }
  if (!write_file(
          out_path, [&](std::ostream& f) { write_mocap_csv(f, result.mocap, stamp); }, err))
    return 1;
  if (!truth_path.empty() &&
      !write_file(
          truth_path, [&](std::ostream& f) { write_pole_truth_csv(f, result.pole_truth); }, err)) {
    return 1;
  }
  if (!vehicle_truth_path.empty() &&
      !write_file(
          vehicle_truth_path, [&](std::ostream& f) { write_vehicle_truth_csv(f, result.vehicle_truth); },
          err)) {
    return 1;
  }

  const PlantConfig& c = result.config;
  out << "scenario " << scenario.name << " (" << scenario_path << "), seed " << scenario.seed
      << (scenario.randomise ? ", randomised" : "") << ", " << scenario.duration_s << " s\n";
  out << format("plant: c_z %.3g, c_xy %.3g, c_rot %.3g g/m^2; mocap latency %.4f s\n",
                c.pole.drag_axial_kgpm2 * 1e3, c.pole.drag_normal_kgpm2 * 1e3,
                c.pole.drag_rotational_kgpm2 * 1e3, c.mocap.latency_s);
  if (result.catch_position_m) {
    const Vec3& p = *result.catch_position_m;
    out << format("catch point (vehicle position): %.4f %.4f %.4f m\n", p.x(), p.y(), p.z());
  }
  if (result.launch_t_s) {
    out << format("launch_t_s = %.4f\n", *result.launch_t_s);
  } else {
    out << "launch_t_s = none\n";
  }
  if (result.impact_t_s) {
    const std::string_view on = contact_name(result.impact_on);
    out << format("impact_t_s = %.4f (pole end %d on %.*s)\n", *result.impact_t_s, result.impact_end,
                  static_cast<int>(on.size()), on.data());
  } else {
    out << "impact_t_s = none\n";
  }
  out << "wrote " << result.mocap.size() << " motion-capture rows to " << out_path << "\n";
  if (!truth_path.empty())
    out << "wrote " << result.pole_truth.size() << " pole truth rows to " << truth_path << "\n";
  return 0;
}

}  // namespace

int record_command(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  try {
    return record(args, out, err);
  } catch (const std::exception& e) {
    err << "hil record: internal error: " << e.what() << "\n";
  } catch (...) {
    err << "hil record: internal error\n";
  }
  return 1;
}

}  // namespace hil
