#include "hil/apps/flight_output.hpp"

#include <cstdio>
#include <fstream>

namespace hil::apps {

void write_time_series(const std::string& path, const std::vector<trials::TimeSample>& samples) {
  std::ofstream ts(path);
  ts << "t_s,v1_x,v1_y,v1_z,v2_x,v2_y,v2_z,pole_x,pole_y,pole_z,pole_nx,pole_ny,pole_nz,task1,task2";
  for (const char* v : {"1", "2"}) {
    for (const char* c : {"plate%s_x", "plate%s_y", "plate%s_z", "plate%s_nx", "plate%s_ny", "plate%s_nz"}) {
      char name[32];
      std::snprintf(name, sizeof name, c, v);
      ts << "," << name;
    }
  }
  ts << ",end0_x,end0_y,end0_z,end1_x,end1_y,end1_z";
  ts << ",v1_thrust_mps2,v1_p_radps,v1_q_radps,v1_r_radps,v2_thrust_mps2,v2_p_radps,v2_q_radps,v2_r_radps\n";
  for (const trials::TimeSample& s : samples) {
    char line[1024];
    int n = std::snprintf(
        line, sizeof line, "%.3f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%s,%s", s.t_s,
        s.vehicle1_m.x(), s.vehicle1_m.y(), s.vehicle1_m.z(), s.vehicle2_m.x(), s.vehicle2_m.y(),
        s.vehicle2_m.z(), s.pole_m.x(), s.pole_m.y(), s.pole_m.z(), s.pole_axis.x(), s.pole_axis.y(),
        s.pole_axis.z(), s.task1.c_str(), s.task2.c_str());
    for (int i = 0; i < 2; ++i) {
      n += std::snprintf(line + n, sizeof line - n, ",%.4f,%.4f,%.4f,%.4f,%.4f,%.4f", s.plate_m[i].x(),
                         s.plate_m[i].y(), s.plate_m[i].z(), s.plate_normal[i].x(), s.plate_normal[i].y(),
                         s.plate_normal[i].z());
    }
    for (int i = 0; i < 2; ++i) {
      n += std::snprintf(line + n, sizeof line - n, ",%.4f,%.4f,%.4f", s.pole_end_m[i].x(),
                         s.pole_end_m[i].y(), s.pole_end_m[i].z());
    }
    for (int i = 0; i < 2; ++i) {
      n += std::snprintf(line + n, sizeof line - n, ",%.3f,%.3f,%.3f,%.3f", s.thrust_cmd_mps2[i],
                         s.rate_cmd_radps[i].x(), s.rate_cmd_radps[i].y(), s.rate_cmd_radps[i].z());
    }
    ts << line << "\n";
  }
}

void print_identification(const gs::runtime::GroundStation& gs, const Plant& truth) {
  const PlantConfig& plant = truth.config();
  for (const pa::VehicleId v : pa::kActVehicles) {
    const std::size_t slot = pa::act_slot(v);
    const double truth_s =
        plant.vehicle.motor_time_constant_s * plant.vehicle.motor_time_constant_scale[slot];
    const auto& result = gs.motor_identification(v);
    std::printf("         vehicle %u motors: ", static_cast<unsigned>(v.node()));
    if (!result) {
      std::printf("not identified");
    } else if (!result->identified) {
      std::printf("identification refused (%s)",
                  std::string(gs::estimation::refusal_name(result->refusal)).c_str());
    } else {
      const gs::estimation::MotorIdentification& id = *result->identified;
      std::printf("lag %.1f ms (95 %%: %.1f-%.1f), inertia gain %.2f, round trip %.0f ms, rms %.3f rad/s",
                  1e3 * id.time_constant_s, 1e3 * id.time_constant_low_s, 1e3 * id.time_constant_high_s,
                  id.inertia_gain, 1e3 * id.round_trip_s, id.rms_radps);
    }
    std::printf(
        "; equalised to %.1f ms, inertia %.2f of the file's; thrust gain %.3f; the plant's lag %.1f ms, "
        "inertia gain %.2f, thrust gain %.3f\n",
        1e3 * gs.equalised_motor_time_constant_s(v), gs.on_board_inertia_scale(v), gs.thrust_gain(v).gain(),
        1e3 * truth_s, 1.0 / plant.vehicle.inertia_scale[slot], truth.true_thrust_gain(v));
  }
}

}  // namespace hil::apps
