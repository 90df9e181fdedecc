#include "hil/plant/recorder.hpp"

#include <cstdio>
#include <exception>
#include <fstream>
#include <optional>

#include "hil/plant/key_value_file.hpp"

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
    out << format("%.6f,%.*s,%.6f,%.6f,%.6f,%.9f,%.9f,%.9f,%.9f\n", t, static_cast<int>(name.size()), name.data(),
                  r.position_m.x(), r.position_m.y(), r.position_m.z(), r.attitude.w(), r.attitude.x(),
                  r.attitude.y(), r.attitude.z());
  }
}

void write_pole_truth_csv(std::ostream& out, const std::vector<PoleTruthRow>& rows) {
  out << "t,px,py,pz,vx,vy,vz,nx,ny,nz,wx,wy,wz,contact\n";
  for (const PoleTruthRow& r : rows) {
    const std::string_view contact = contact_name(r.contact);
    out << format("%.6f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.*s\n", r.t_s, r.position_m.x(),
                  r.position_m.y(), r.position_m.z(), r.velocity_mps.x(), r.velocity_mps.y(), r.velocity_mps.z(),
                  r.axis.x(), r.axis.y(), r.axis.z(), r.rate_radps.x(), r.rate_radps.y(), r.rate_radps.z(),
                  static_cast<int>(contact.size()), contact.data());
  }
}

void write_vehicle_truth_csv(std::ostream& out, const std::vector<VehicleTruthRow>& rows) {
  out << "t,vehicle,x,y,z,vx,vy,vz,qw,qx,qy,qz,wx,wy,wz,f0,f1,f2,f3\n";
  for (const VehicleTruthRow& r : rows) {
    const RigidBodyState& b = r.state.body;
    const Quat q = b.attitude.w() < 0.0 ? Quat(-b.attitude.w(), -b.attitude.x(), -b.attitude.y(), -b.attitude.z())
                                        : b.attitude;
    const auto& f = r.state.motor_thrust_N;
    out << format("%.6f,vehicle%d,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.6f,%.6f,%.6f,%.6f\n",
                  r.t_s, r.vehicle + 1, b.position_m.x(), b.position_m.y(), b.position_m.z(), b.velocity_mps.x(),
                  b.velocity_mps.y(), b.velocity_mps.z(), q.w(), q.x(), q.y(), q.z(), b.rate_body_radps.x(),
                  b.rate_body_radps.y(), b.rate_body_radps.z(), f[0], f[1], f[2], f[3]);
  }
}

void print_record_usage(std::ostream& out) {
  out << "usage: hil record --scenario FILE --out FILE.csv [--truth FILE.csv] [--vehicle-truth FILE.csv]\n"
         "                  [--seed N] [--randomise] [--stamp delivery|capture]\n"
         "\n"
         "Runs a scenario (hil/config/scenarios/*.scenario) on the truth plant and writes the\n"
         "motion-capture log (t,body,x,y,z,qw,qx,qy,qz), optionally the true pole state\n"
         "(t,px,py,pz,vx,vy,vz,nx,ny,nz,wx,wy,wz,contact) and the true vehicle states.\n"
         "  --seed N       overrides the scenario's seed (noise, IMU bias, randomisation)\n"
         "  --randomise    draws the uncertain plant parameters from the seed\n"
         "  --stamp        delivery (default): t is when the frame reached the ground station;\n"
         "                 capture: t is when the poses were true\n";
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
  std::string scenario_path;
  std::string out_path;
  std::string truth_path;
  std::string vehicle_truth_path;
  std::optional<std::uint64_t> seed;
  bool randomise = false;
  MocapStamp stamp = MocapStamp::delivery;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--help" || a == "-h") {
      print_record_usage(out);
      return 0;
    }
    if (a == "--randomise") {
      randomise = true;
      continue;
    }
    const bool takes_value =
        a == "--scenario" || a == "--out" || a == "--truth" || a == "--vehicle-truth" || a == "--seed" || a == "--stamp";
    if (!takes_value) {
      err << "hil record: unknown argument '" << a << "'\n\n";
      print_record_usage(err);
      return 2;
    }
    if (i + 1 >= args.size()) {
      err << "hil record: " << a << " needs a value\n\n";
      print_record_usage(err);
      return 2;
    }
    const std::string& v = args[++i];
    if (a == "--scenario") {
      scenario_path = v;
    } else if (a == "--out") {
      out_path = v;
    } else if (a == "--truth") {
      truth_path = v;
    } else if (a == "--vehicle-truth") {
      vehicle_truth_path = v;
    } else if (a == "--seed") {
      const auto n = parse_integer(v);
      if (!n || *n < 0) {
        err << "hil record: --seed needs a non-negative integer, got '" << v << "'\n";
        return 2;
      }
      seed = static_cast<std::uint64_t>(*n);
    } else {
      if (v == "delivery") {
        stamp = MocapStamp::delivery;
      } else if (v == "capture") {
        stamp = MocapStamp::capture;
      } else {
        err << "hil record: --stamp must be delivery or capture, got '" << v << "'\n";
        return 2;
      }
    }
  }
  if (scenario_path.empty() || out_path.empty()) {
    err << "hil record: " << (scenario_path.empty() ? "--scenario" : "--out") << " is required\n\n";
    print_record_usage(err);
    return 2;
  }

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
  if (!write_file(out_path, [&](std::ostream& f) { write_mocap_csv(f, result.mocap, stamp); }, err)) return 1;
  if (!truth_path.empty() &&
      !write_file(truth_path, [&](std::ostream& f) { write_pole_truth_csv(f, result.pole_truth); }, err)) {
    return 1;
  }
  if (!vehicle_truth_path.empty() &&
      !write_file(vehicle_truth_path, [&](std::ostream& f) { write_vehicle_truth_csv(f, result.vehicle_truth); }, err)) {
    return 1;
  }

  const PlantConfig& c = result.config;
  out << "scenario " << scenario.name << " (" << scenario_path << "), seed " << scenario.seed
      << (scenario.randomise ? ", randomised" : "") << ", " << scenario.duration_s << " s\n";
  out << format("plant: c_z %.3g, c_xy %.3g, c_rot %.3g g/m^2; mocap latency %.4f s\n", c.pole.drag_axial_kgpm2 * 1e3,
                c.pole.drag_normal_kgpm2 * 1e3, c.pole.drag_rotational_kgpm2 * 1e3, c.mocap.latency_s);
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
  if (!truth_path.empty()) out << "wrote " << result.pole_truth.size() << " pole truth rows to " << truth_path << "\n";
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
