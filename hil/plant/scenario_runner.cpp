#include "hil/plant/scenario_runner.hpp"

#include <cmath>
#include <exception>

#include "hil/plant/pole_balancer.hpp"
#include "hil/plant/randomisation.hpp"
#include "hil/plant/vehicle_controller.hpp"

namespace hil {

namespace {

// The launched pole, moved unaccelerated by `dt_s` (negative: before the launch).
PoleState carried(const PoleState& launch, double dt_s) {
  const Vec3 rate = launch.body.rate_inertial_radps();
  PoleState p = launch;
  p.body.position_m += dt_s * launch.body.velocity_mps;
  const double angle = rate.norm() * dt_s;
  if (rate.norm() > 0.0)
    p.body.attitude = Quat(Eigen::AngleAxisd(angle, rate.normalized())) * launch.body.attitude;
  p.body.attitude.normalize();
  p.body.rate_body_radps = p.body.attitude.conjugate() * rate;
  return p;
}

// Flies the launched pole alone and returns where its lowest end comes down through the
// catch height.
bool find_catch_point(const PlantConfig& config, const Scenario& s, Vec3& out, std::string& error) {
  Plant probe(config, s.seed);
  probe.set_vehicle(pa::kVehicle1, probe.parked_vehicle(-1e4, 0.0, 0.0));
  probe.set_vehicle(pa::kVehicle2, probe.parked_vehicle(1e4, 0.0, 0.0, pa::kVehicle2));
  probe.set_pole(launch_state(s));
  auto ends = [&] {
    return std::array<Vec3, 2>{pole_end_m(probe.pole(), config.pole, 0),
                               pole_end_m(probe.pole(), config.pole, 1)};
  };
  std::array<Vec3, 2> previous = ends();
  const MotorCommands off{};
  for (int k = 0; k < 20000; ++k) {
    probe.step(0.001, off, off);
    const std::array<Vec3, 2> now = ends();
    const int low = now[0].z() < now[1].z() ? 0 : 1;
    const double h = s.catch_height_m;
    if (previous[low].z() > h && now[low].z() <= h) {
      const double f = (previous[low].z() - h) / (previous[low].z() - now[low].z());
      out = previous[low] + f * (now[low] - previous[low]);
      return true;
    }
    previous = now;
  }
  error = s.source + ": the launched pole never comes down through catch_height_m = " +
          std::to_string(s.catch_height_m) + " m within 20 s, so vehicle" +
          (s.vehicle[0].position_auto ? "1" : "2") + "_position_m = auto has no place";
  return false;
}

// A thrower carrying the pole's lower end (end 0) on the centre of its level plate, moving with
// it, motors off.
VehicleState carrying(const Plant& plant, const PoleState& pole, double yaw_rad) {
  const PlantConfig& c = plant.config();
  VehicleState v;
  v.body.attitude = Quat(Eigen::AngleAxisd(yaw_rad, Vec3::UnitZ()));
  const Vec3 end = pole_end_m(pole, c.pole, 0);
  v.body.position_m = end - Vec3(0.0, 0.0, c.vehicle.plate_height_m);
  v.body.velocity_mps =
      pole.body.velocity_mps + pole.body.rate_inertial_radps().cross(end - pole.body.position_m);
  return v;
}

Quat canonical(const Quat& q) { return q.w() < 0.0 ? Quat(-q.w(), -q.x(), -q.y(), -q.z()) : q; }

bool run(const Scenario& s, ScenarioResult& out, std::string& error) {
  out = ScenarioResult{};
  const PlantConfig config = s.randomise ? randomised(s.plant, s.seed) : s.plant;
  out.config = config;
  Plant plant(config, s.seed);
  const double dt = 1.0 / config.imu.rate_Hz;
  out.tick_s = dt;
  const bool launching = s.pole_start == PoleStart::launch;
  const PoleState launch = launching ? launch_state(s) : PoleState{};

  // Vehicles.
  std::array<Vec3, 2> hold_position{s.vehicle[0].position_m, s.vehicle[1].position_m};
  for (int i = 0; i < 2; ++i) {
    const ScenarioVehicle& v = s.vehicle[i];
    const pa::VehicleId id = pa::kActVehicles[i];
    if (v.position_auto) {
      Vec3 point;
      if (!find_catch_point(config, s, point, error)) return false;
      hold_position[i] = Vec3(point.x() + s.catch_offset_m.x(), point.y() + s.catch_offset_m.y(),
                              s.catch_height_m - config.vehicle.plate_height_m);
      out.catch_position_m = hold_position[i];
    }
    if (v.mode == VehicleMode::parked) {
      plant.set_vehicle(id, plant.parked_vehicle(v.position_m.x(), v.position_m.y(), v.yaw_rad, id));
    } else {
      VehicleState state = plant.hovering_vehicle(hold_position[i], v.yaw_rad, id);
      if (!launching && s.balance_vehicle == id) {
        for (double& f : state.motor_thrust_N) f += config.pole.mass_kg * config.gravity_mps2 / 4.0;
      }
      plant.set_vehicle(id, state);
    }
  }

  // The pole, and a thrower under it.
  int thrower = -1;
  for (int i = 0; i < 2; ++i) {
    if (s.vehicle[i].mode == VehicleMode::thrower) thrower = i;
  }
  auto carry = [&](double t_s) {
    const PoleState pole = carried(launch, t_s - s.launch_time_s);
    plant.set_pole(pole);
    if (thrower >= 0)
      plant.set_vehicle(pa::kActVehicles[thrower], carrying(plant, pole, s.vehicle[thrower].yaw_rad));
  };
  if (launching) {
    carry(0.0);
  } else {
    const pa::VehicleId v = s.balance_vehicle;
    const Vec3 axis(std::sin(s.balance_tilt_rad), 0.0, std::cos(s.balance_tilt_rad));
    plant.set_pole(Plant::make_pole(plant.plate_centre_m(v) - config.pole.end_along_axis_m(0) * axis, axis,
                                    Vec3::Zero(), Vec3::Zero()));
  }

  std::array<VehicleController, 2> controllers{VehicleController(s.plant.vehicle, s.plant.gravity_mps2),
                                               VehicleController(s.plant.vehicle, s.plant.gravity_mps2)};
  const BalancerGains balancer =
      balancer_gains(s.plant.pole.half_length_m, s.plant.gravity_mps2, s.balance_lambda_radps);
  std::array<bool, 2> caught{false, false};
  if (launching) out.launch_t_s = s.launch_time_s;

  const long long ticks = std::llround(s.duration_s / dt);
  out.pole_truth.reserve(static_cast<std::size_t>(ticks));
  out.vehicle_truth.reserve(static_cast<std::size_t>(2 * ticks));
  for (long long k = 0; k < ticks; ++k) {
    std::array<MotorCommands, 2> commands{};
    for (int i = 0; i < 2; ++i) {
      const ScenarioVehicle& v = s.vehicle[i];
      const pa::VehicleId id = pa::kActVehicles[i];
      if (v.mode == VehicleMode::parked) continue;
      // A thrower carries the pole with its motors off, and falls away from it after the launch.
      if (v.mode == VehicleMode::thrower && plant.t_s() < s.launch_time_s + s.thrower_release_s - 1e-9)
        continue;
      VehicleSetpoint sp;
      sp.position_m = hold_position[i];
      sp.yaw_rad = v.yaw_rad;
      const bool balancing =
          v.mode == VehicleMode::balance || (caught[i] && v.after_catch == VehicleMode::balance);
      const Contact plate = i == 0 ? Contact::vehicle1 : Contact::vehicle2;
      const int supported = plant.pole_end_contact(0) == plate   ? 0
                            : plant.pole_end_contact(1) == plate ? 1
                                                                 : -1;
      if (balancing && supported >= 0) {
        sp.hold_horizontal = false;
        sp.acceleration_mps2 =
            balance_acceleration(balancer, plant.pole(), supported, plant.vehicle(id), hold_position[i]);
      }
      commands[i] = controllers[i].update(plant.vehicle(id), sp, dt);
    }
    plant.step(dt, commands[0], commands[1]);
    // Until the launch the thrower carries the pole: it moves with the launch state unaccelerated,
    // and is exactly in the launch state at the launch.
    if (launching && plant.t_s() < s.launch_time_s + 1e-9) carry(plant.t_s());

    CapturedFrame frame;
    while (plant.pop_mocap(frame)) {
      for (int b = 0; b < 3; ++b) {
        const CapturedPose& pose = frame.pose[b];
        if (!pose.seen) continue;
        out.mocap.push_back(MocapRow{frame.delivery_t_s, frame.capture_t_s, static_cast<Body>(b),
                                     pose.position_m, canonical(pose.attitude)});
      }
    }
    for (int i = 0; i < 2; ++i) {
      ImuSample sample;
      const pa::VehicleId id = pa::kActVehicles[i];
      while (plant.pop_imu(id, sample)) out.imu[i].push_back(sample);
      out.vehicle_truth.push_back(VehicleTruthRow{plant.t_s(), id, plant.vehicle(id)});
    }
    const PoleState& pole = plant.pole();
    // While carried, the pole stands on the thrower's plate by construction.
    const bool carried_now = launching && thrower >= 0 && plant.t_s() < s.launch_time_s - 1e-9;
    const Contact contact =
        carried_now ? (thrower == 0 ? Contact::vehicle1 : Contact::vehicle2) : plant.pole_contact();
    out.pole_truth.push_back(PoleTruthRow{plant.t_s(), pole.body.position_m, pole.body.velocity_mps,
                                          pole.axis(), pole.body.rate_inertial_radps(), contact});
    for (const PoleContactEvent& e : plant.take_contact_events()) {
      out.contact_events.push_back(e);
      if (!e.begins || e.surface == Surface::floor) continue;
      const int v = e.surface == Surface::plate1 ? 0 : 1;
      caught[v] = true;
      if (launching && !out.impact_t_s && e.t_s >= s.launch_time_s) {
        out.impact_t_s = e.t_s;
        out.impact_on = contact_of(e.surface);
        out.impact_end = e.end;
      }
    }
  }
  return true;
}

}  // namespace

PoleState launch_state(const Scenario& s) {
  const double lower_end_m = -s.plant.pole.end_along_axis_m(0);  // end 0 to the centre of mass
  const double a = s.pole_tilt_rad;
  const double h = s.pole_tilt_heading_rad;
  const Vec3 heading(std::cos(h), std::sin(h), 0.0);
  const Vec3 axis = std::sin(a) * heading + std::cos(a) * Vec3::UnitZ();
  // Tilting towards the heading is a rotation about e_z x heading.
  const Vec3 rate = s.pole_tilt_rate_radps * Vec3::UnitZ().cross(heading);
  Vec3 centre = s.pole_position_m;
  Vec3 velocity = s.pole_velocity_mps;
  if (s.launch_reference == LaunchReference::lower_end) {
    centre += lower_end_m * axis;
    velocity += rate.cross(lower_end_m * axis);
  }
  return Plant::make_pole(centre, axis, velocity, rate);
}

bool run_scenario(const Scenario& scenario, ScenarioResult& out, std::string& error) {
  try {
    return run(scenario, out, error);
  } catch (const std::exception& e) {
    error = scenario.source + ": " + e.what();
  } catch (...) {
    error = scenario.source + ": the scenario could not be run";
  }
  return false;
}

}  // namespace hil
