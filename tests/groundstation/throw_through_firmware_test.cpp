// The optimal throw (34) of throw_on_plant_test.cpp flown again on the HIL truth plant, but with
// vehicle 1 flown by the REAL firmware core (hil/sil/firmware_vehicle.hpp: rate loop kp 40/s,
// ki 40/s^2, mixer, supervisor, impact detector, at 1 kHz in lockstep through HIL_IMU /
// HIL_MOTORS frames) instead of the stand-in body-rate loop hil::VehicleController::track_rates.
// The ground station's side is what it would send over the protocol: GS_HEARTBEAT at 50 Hz, an
// ARM command, and from then on one RATE_THRUST frame every 5 ms (docs/architecture.md "One tick of
// the system"), quantised by the frame to 2 mrad/s and 0.01 m/s^2. The estimator runs beside
// it, as in flight, on the plant's motion capture and on the commands as sent.
//
// Differences from the stand-in (measured, see the figures printed and the comments below):
// - the stand-in computes its motor commands from the TRUE body rates in the same millisecond,
//   with a P law (40/s) and the gyroscopic terms cancelled, and shortens the motors' 30 ms lag
//   with a 10 ms lead; the firmware runs a PI law (kp 40/s, ki 40/s^2) on its measured gyro
//   (noise, bias, 1.1 mrad/s quantisation), one IMU period late, through the motors' own lag.
//   The lead alone is not what matters: the stand-in flown without it (motor_response_s = 0)
//   still flies this throw with 0.012 rad of tilt error and releases at T + 40 ms;
// - RATE_THRUST quantisation (1 mrad/s and 0.005 m/s^2 at most) is far below the TV-LQR's
//   tolerances (2 rad/s, 2 m/s^2 in throw_tracking.hpp) and does not matter.
// - the pole must be balanced ACROSS the throw's plane too: the planar TV-LQR leaves the pole's
//   sideways tilt open-loop, and it is as unstable as the tilt in the plane. The stand-in test
//   gets away without it because its plant starts and stays exactly symmetric; here the IMU's
//   noise and biases break the symmetry, and without the lateral balancing (flight loop below)
//   the pole fell sideways and left the plate 84 ms before T. With it, the firmware flies the
//   throw as the stand-in does.
//
// Start. The firmware starts disarmed, and a disarmed firmware commands the motors off. The
// vehicle is placed hovering in the air with the pole upright on its plate (as in
// throw_on_plant_test.cpp); the ground station sends a heartbeat, a zero-thrust setpoint and ARM
// on the first tick (fw/supervisor.hpp: ARM needs a live heartbeat and the setpoint thrust at 0,
// not the floor), and a hover setpoint on the next 5 ms frame, which is above
// takeoff_thrust_mps2 and so takes the vehicle from armed to flying. The motors sag for those
// few milliseconds; then the ground station balances the pole with the balancing LQR of Section
// VII-A for a settling hover before the throw starts from where the balancing left it.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "groundstation/control/balancing_lqr.hpp"
#include "groundstation/estimation/state_estimator.hpp"
#include "groundstation/planning/catch_point_predictor.hpp"
#include "groundstation/planning/throw_command.hpp"
#include "groundstation/planning/throw_planner.hpp"
#include "groundstation/planning/throw_tracking.hpp"
#include "hil/plant/plant.hpp"
#include "hil/sil/firmware_vehicle.hpp"
#include "pa/protocol.hpp"
#include "plant_throw_support.hpp"

namespace {

using gs::model::PlanarInput;
using gs::model::PlanarState;
namespace planar = gs::model::planar;
namespace bal = gs::control::balancing;
namespace proto = pa::proto;
using namespace plant_throw;

constexpr double kFrame_s = 0.005;                    // motion capture and ground-station commands, 200 Hz
constexpr int kTicksPerFrame = 5;                     // firmware ticks (1 ms) per frame
constexpr int kHeartbeatTicks = 20;                   // GS_HEARTBEAT at 50 Hz
constexpr std::uint8_t kNode = pa::kVehicle1.node();  // on the wire
constexpr std::uint16_t kSession = 0x7A11;
constexpr double kSettle_s = 2.0;  // balancing hover before the throw
// The throw before its terminal phase (the last 0.3 s, where the pitch rate swings fastest).
constexpr double kTrackedUntil_s = 2.2;

// What the ground station heard from the vehicle.
struct Heard {
  std::vector<std::pair<double, proto::Impact>> impacts;  // (plant time received, IMPACT)
  std::vector<std::pair<double, proto::Mode>> modes;      // each new VEHICLE_HEARTBEAT mode
  std::optional<proto::CommandAck> arm_ack;
  int undecodable = 0;
};

struct Flight {
  double throw_start_s = 0.0;                                     // plant time of the plan's t = 0
  PlanarState<double> start_state = PlanarState<double>::Zero();  // planar state then
  double settle_tilt_max_rad = 0.0;   // |pole tilt| over the last second of the settling hover
  std::optional<double> release_t_s;  // plan time: the plate's force on the pole vanishes
  std::optional<double> launch_t_s;   // plan time: the pole's end leaves the plate's surface
  PlanarState<double> launch_state = PlanarState<double>::Zero();
  std::vector<gs::estimation::ModeSwitch> switches;  // the estimator's, oldest first (plant time)
  double max_tilt_error_rad = 0.0;                   // |alpha - alpha_ref| before T
  double max_position_error_m = 0.0;                 // |(x, z) - (x, z)_ref| before T
  double max_pitch_error_rad = 0.0;                  // |theta - theta_ref| before T
  // The same up to kTrackedUntil_s, before the terminal phase's fast pitch-rate swing.
  double tracked_tilt_error_rad = 0.0;
  double tracked_position_error_m = 0.0;
  double tracked_pitch_error_rad = 0.0;
  std::optional<double> diverged_t_s;         // plan time the tilt error first exceeds 0.05 rad
  double max_rate_quantisation_radps = 0.0;   // |sent - asked| pitch rate
  double max_thrust_quantisation_mps2 = 0.0;  // |sent - asked| thrust
  double catch_error_m = -1.0;                // predicted vs true crossing, 0.1 s after the release
  double catch_error_late_m = -1.0;           // ... 0.15 s before the crossing
  std::optional<double> crossing_t_s;         // plan time
  bool flying_throughout = true;              // the firmware's own mode stayed `flying` from take-off
  proto::Mode worst_mode = proto::Mode::flying;
  std::uint64_t missed_ticks = 0;
  std::uint64_t samples_fed = 0;
  Heard heard;
};

Flight fly_throw_through_firmware(double catch_height_m) {
  const gs::planning::ThrowProblem problem;
  const gs::planning::ThrowPlan plan = gs::planning::plan_throw(problem);
  REQUIRE(plan.success);
  const gs::planning::ThrowTracker tracker(plan.trajectory);
  REQUIRE(tracker.valid());
  const double T = problem.duration_s;
  const gs::control::LqrGain balancing = gs::control::balancing_lqr();
  REQUIRE(balancing.ok);

  hil::PlantConfig config;  // the documented defaults (hil/config/plant.yaml), as throw_on_plant
  hil::sil::Lockstep rig(config, 7);
  hil::Plant& plant = rig.plant();
  hil::sil::FirmwareVehicle& firmware =
      rig.attach_firmware(hil::sil::firmware_config_for(config.vehicle, pa::VehicleId(kNode)));
  place_for_throw(plant);
  const double L = config.pole.half_length_m;
  // The paper's models leave the pole's weight off the vehicle (Section II); the plate carries
  // it, so the balancing hover adds it to the collective (m_p g / m_v, 0.48 m/s^2) instead of
  // sagging by it against the LQR's height gain. The throw itself gets the TV-LQR's output only,
  // as on the stand-in.
  const double pole_weight_mps2 = config.pole.mass_kg * config.gravity_mps2 / config.vehicle.mass_kg;

  Flight flight;
  gs::estimation::StateEstimator est;
  long tick = 0;
  std::uint8_t heartbeat_seq = 0;
  unsigned setpoint_seq = 0;
  // Every ground frame followed by its AUTH, as the ground station sends it (docs/security.md).
  pa::auth::Signer signer(hil::sil::simulation_key(pa::VehicleId(kNode)));
  signer.start_session(firmware.firmware().guard().nonce(), 0);
  auto inject_signed = [&](const proto::Frame& f) {
    proto::Frame auth;
    REQUIRE(signer.sign(f, auth));
    firmware.inject(f);
    firmware.inject(auth);
  };
  auto send = [&](const auto& message, std::uint8_t node) {
    proto::Frame f;
    REQUIRE(proto::encode(message, node, f));
    inject_signed(f);
  };
  // One RATE_THRUST frame; returns what the frame carries (the vehicle flies the decoded values).
  auto send_setpoint = [&](double thrust_mps2, const hil::Vec3& rates_radps) {
    proto::RateThrust sp{{static_cast<float>(rates_radps.x()), static_cast<float>(rates_radps.y()),
                          static_cast<float>(rates_radps.z())},
                         static_cast<float>(thrust_mps2),
                         static_cast<std::uint8_t>(setpoint_seq++ & 0x0Fu)};
    proto::Frame f;
    REQUIRE(proto::encode(sp, kNode, f));
    proto::Message m;
    REQUIRE(proto::decode(f, m) == proto::DecodeStatus::ok);
    inject_signed(f);
    return m.rate_thrust;
  };
  auto listen = [&] {
    for (const proto::Frame& f : firmware.take_sent()) {
      proto::Message m;
      if (proto::decode(f, m) != proto::DecodeStatus::ok) {
        ++flight.heard.undecodable;
        continue;
      }
      if (m.type == proto::Type::impact) {
        flight.heard.impacts.emplace_back(rig.t_s(), m.impact);
      } else if (m.type == proto::Type::command_ack && m.command_ack.code == proto::CommandCode::arm) {
        flight.heard.arm_ack = m.command_ack;
      } else if (m.type == proto::Type::vehicle_heartbeat) {
        auto& modes = flight.heard.modes;
        if (modes.empty() || modes.back().second != m.vehicle_heartbeat.mode)
          modes.emplace_back(rig.t_s(), m.vehicle_heartbeat.mode);
      }
    }
  };

  // The arm sequence on the first tick: heartbeat, a zero-thrust setpoint, ARM.
  send(proto::GsHeartbeat{0, kSession, proto::GroundState::active, heartbeat_seq++}, kNode);
  send_setpoint(0.0, hil::Vec3::Zero());
  send(proto::Command{proto::CommandCode::arm, 0, kSession, 0}, kNode);

  const double t_end = kSettle_s + T + 1.6;
  CatchCheck catches(catch_height_m);
  bool took_off = false;
  gs::model::VehicleInput command;  // what the ground station sends, once per frame

  for (int frame = 0; frame * kFrame_s < t_end; ++frame) {
    const double t = frame * kFrame_s;  // plant time
    const double tau = t - kSettle_s;   // plan time
    if (frame == 0) {
      command.a_q_mps2 = 0.0;
      command.omega_radps.setZero();
    } else if (tau < -1e-9) {
      // The settling hover: the balancing LQR (Section VII-A) about the plan's origin.
      Eigen::VectorXd u = -balancing.K * balancing_state(plant, L);
      u(bal::kThrust) += config.gravity_mps2 + pole_weight_mps2;
      command = gs::control::from_balancing_input(u);
      command.a_q_mps2 =
          std::clamp(command.a_q_mps2, problem.limits.a_q_min_mps2, problem.limits.a_q_max_mps2);
      if (tau > -1.0 - 1e-9) {
        flight.settle_tilt_max_rad =
            std::max(flight.settle_tilt_max_rad, std::acos(std::min(1.0, plant.pole().axis().z())));
      }
    } else if (tau < T - 1e-9) {
      if (std::abs(tau) < 1e-9) {
        flight.throw_start_s = t;
        flight.start_state = planar_state(plant);
      }
      const PlanarState<double> s = planar_state(plant);
      // The ground station's 3D throw command (throw_command.hpp): the planar TV-LQR in the
      // throw's plane, the pole balanced across it. Without the second part, the IMU's noise and
      // biases, which break the plant's symmetry, grew into a sideways fall: b/L went from 1e-4
      // at the start to 0.26 at t = 2.0 s and 0.98 at 2.4 s, and the pole left the plate 84 ms
      // before T.
      command =
          gs::planning::throw_command(tracker, balancing, tau, s, balancing_state(plant, L), problem.limits);
      const PlanarState<double> ref = tracker.reference().state_at(tau);
      const double tilt_error_rad = std::abs(s(planar::kAlpha) - ref(planar::kAlpha));
      flight.max_tilt_error_rad = std::max(flight.max_tilt_error_rad, tilt_error_rad);
      if (tau < kTrackedUntil_s) {
        flight.tracked_tilt_error_rad = std::max(flight.tracked_tilt_error_rad, tilt_error_rad);
        flight.tracked_pitch_error_rad =
            std::max(flight.tracked_pitch_error_rad, std::abs(s(planar::kTheta) - ref(planar::kTheta)));
        flight.tracked_position_error_m =
            std::max(flight.tracked_position_error_m,
                     std::hypot(s(planar::kX) - ref(planar::kX), s(planar::kZ) - ref(planar::kZ)));
      }
      if (tilt_error_rad > 0.05 && !flight.diverged_t_s) flight.diverged_t_s = tau;
      flight.max_pitch_error_rad =
          std::max(flight.max_pitch_error_rad, std::abs(s(planar::kTheta) - ref(planar::kTheta)));
      flight.max_position_error_m =
          std::max(flight.max_position_error_m,
                   std::hypot(s(planar::kX) - ref(planar::kX), s(planar::kZ) - ref(planar::kZ)));
    } else {
      // The release, as on the stand-in: the thrust drops to its minimum and the plate pitches
      // back at the plan's launch rate (Omega_y,T > 0) for 0.1 s, the thrust stays low for 0.3 s
      // so that the plate keeps falling away, then the vehicle levels at hover thrust.
      const hil::Mat3 r = plant.vehicle(pa::kVehicle1).body.rotation();
      command.a_q_mps2 = tau < T + 0.3 ? problem.limits.a_q_min_mps2 : config.gravity_mps2;
      command.omega_radps = tau < T + 0.1 ? hil::Vec3(0.0, problem.launch_pitch_rate_radps, 0.0)
                                          : hil::Vec3(0.0, -8.0 * std::atan2(r(0, 2), r(2, 2)), 0.0);
    }
    if (frame > 0) {
      const proto::RateThrust sent = send_setpoint(command.a_q_mps2, command.omega_radps);
      if (tau > -1e-9 && tau < T - 1e-9) {
        flight.max_rate_quantisation_radps =
            std::max(flight.max_rate_quantisation_radps,
                     std::abs(double(sent.rate_radps[1]) - command.omega_radps.y()));
        flight.max_thrust_quantisation_mps2 = std::max(flight.max_thrust_quantisation_mps2,
                                                       std::abs(double(sent.thrust_mps2) - command.a_q_mps2));
      }
      // The estimator is told what the vehicle was sent, after the frame's quantisation.
      command.a_q_mps2 = sent.thrust_mps2;
      command.omega_radps = hil::Vec3(sent.rate_radps[0], sent.rate_radps[1], sent.rate_radps[2]);
    }
    // The firmware acts on a frame after checking its AUTH over two more ticks (docs/security.md).
    est.set_command(pa::kVehicle1, t + pa::auth::TagCheck::kSteps * 1e-3, command);

    for (int k = 0; k < kTicksPerFrame; ++k, ++tick) {
      if (tick > 0 && tick % kHeartbeatTicks == 0) {
        send(proto::GsHeartbeat{static_cast<std::uint32_t>(tick), kSession, proto::GroundState::active,
                                heartbeat_seq++},
             kNode);
      }
      rig.step();
      listen();
      const proto::Mode mode = firmware.firmware().mode();
      if (mode == proto::Mode::flying) took_off = true;
      if (took_off && mode != proto::Mode::flying) {
        flight.flying_throughout = false;
        flight.worst_mode = mode;
      }
      const double plan_t = rig.t_s() - kSettle_s;
      if (!flight.release_t_s && plan_t > T - 0.2 &&
          plant.pole_end_force_N(0, hil::Surface::plate1).norm() == 0.0) {
        flight.release_t_s = plan_t;
      }
      for (const hil::PoleContactEvent& e : plant.take_contact_events()) {
        if (!flight.launch_t_s && !e.begins && e.surface == hil::Surface::plate1 && e.t_s - kSettle_s > 0.5) {
          flight.launch_t_s = e.t_s - kSettle_s;
          flight.launch_state = planar_state(plant);
        }
      }
      catches.watch(plant, plan_t, flight.launch_t_s.has_value());
    }

    hil::CapturedFrame f;
    while (plant.pop_mocap(f)) {
      est.update(to_estimator_frame(f));
      if (flight.launch_t_s && est.mode() == gs::estimation::PoleMode::free) {
        catches.predicted(f.capture_t_s - kSettle_s, gs::planning::predict_catch_point(
                                                         est.pole().state, catch_height_m, est.pole_model()));
      }
    }
  }
  flight.switches = est.recent_switches();
  flight.missed_ticks = firmware.missed_ticks();
  flight.samples_fed = firmware.samples_fed();
  REQUIRE(flight.release_t_s);
  REQUIRE(flight.launch_t_s);
  const std::optional<CatchCheck::Errors> misses = catches.errors(*flight.release_t_s);
  REQUIRE(misses);
  flight.crossing_t_s = misses->crossing_t_s;
  flight.catch_error_m = misses->after_release_m;
  flight.catch_error_late_m = misses->before_crossing_m;
  return flight;
}

// The flight, flown once (4.6 s of plant time with the firmware in the loop).
const Flight& the_flight() {
  static const Flight flight = fly_throw_through_firmware(kStart_m.z() + 0.5);
  return flight;
}

void print_flight(const Flight& f) {
  const gs::planning::ThrowProblem problem;
  const double T = problem.duration_s;
  const PlanarState<double> target = problem.launch_state;
  const PlanarState<double>& s0 = f.start_state;
  std::printf("throw through the firmware: after %.1f s of balancing, pole tilt at most %.4f rad "
              "over the last second; start state (x, z, vx, vz, theta, alpha, alpha') = (%.3f, "
              "%.3f, %.3f, %.3f, %.3f, %.4f, %.3f)\n",
              kSettle_s, f.settle_tilt_max_rad, s0(0), s0(1), s0(2), s0(3), s0(4), s0(5), s0(6));
  std::printf("  up to %.2f s: max pole tilt error %.4f rad, position error %.3f m, pitch error "
              "%.3f rad; up to T: %.3f rad, %.3f m, %.3f rad; tilt error above 0.05 rad from "
              "t = %.3f s; RATE_THRUST quantisation at most %.4f rad/s, %.4f m/s^2\n",
              kTrackedUntil_s, f.tracked_tilt_error_rad, f.tracked_position_error_m,
              f.tracked_pitch_error_rad, f.max_tilt_error_rad, f.max_position_error_m, f.max_pitch_error_rad,
              f.diverged_t_s ? *f.diverged_t_s : -1.0, f.max_rate_quantisation_radps,
              f.max_thrust_quantisation_mps2);
  const gs::planning::ThrowTracker tracker(gs::planning::plan_throw(problem).trajectory);
  std::printf("  TV-LQR pitch-rate gains (rad/s per rad of theta error, per rad of alpha error):");
  for (double t : {1.0, 2.0, 2.2, 2.3, 2.4, 2.45, 2.49}) {
    const Eigen::Matrix<double, 2, 7> K = tracker.gain(t);
    std::printf(" t %.2f: %.1f, %.1f;", t, K(planar::kPitchRate, planar::kTheta),
                K(planar::kPitchRate, planar::kAlpha));
  }
  std::printf("\n");
  std::printf("  plate force gone at T %+.1f ms, end off the plate at T %+.1f ms; launch state "
              "(%.3f, %.3f, %.3f, %.3f, %.3f, %.3f, %.3f), planned (%.3f, %.3f, %.3f, %.3f, %.3f, "
              "%.3f, %.3f)\n",
              1e3 * (*f.release_t_s - T), 1e3 * (*f.launch_t_s - T), f.launch_state(0), f.launch_state(1),
              f.launch_state(2), f.launch_state(3), f.launch_state(4), f.launch_state(5), f.launch_state(6),
              target(0), target(1), target(2), target(3), target(4), target(5), target(6));
  for (std::size_t i = 1; i < f.switches.size(); ++i) {
    const gs::estimation::ModeSwitch& s = f.switches[i];
    std::printf("  switch %s -> %s (%s): event at T %+.1f ms, decided at T %+.1f ms, %+.1f frames "
                "from the plate force's end\n",
                std::string(gs::estimation::pole_mode_name(s.from)).c_str(),
                std::string(gs::estimation::pole_mode_name(s.to)).c_str(),
                std::string(gs::estimation::switch_reason_name(s.reason)).c_str(),
                1e3 * (s.event_t_s - kSettle_s - T), 1e3 * (s.detected_t_s - kSettle_s - T),
                (s.detected_t_s - kSettle_s - *f.release_t_s) / kFrame_s);
  }
  std::printf("  catch point %.1f mm off 0.1 s after the release, %.1f mm 0.15 s before the "
              "crossing (T %+.3f s)\n",
              1e3 * f.catch_error_m, 1e3 * f.catch_error_late_m, *f.crossing_t_s - T);
  for (const auto& [t, m] : f.heard.modes)
    std::printf("  VEHICLE_HEARTBEAT mode %d from plant t %.3f s\n", int(m), t);
  std::printf("  %zu IMPACT frames\n", f.heard.impacts.size());
  for (const auto& [t, imp] : f.heard.impacts) {
    std::printf("  IMPACT count %d, %s, class %d, peak %.1f m/s^2, onset at plan time %.4f s\n",
                int(imp.count), imp.final ? "final" : "provisional", int(imp.classification),
                double(imp.peak_mps2), imp.vehicle_time_us * 1e-6 - kSettle_s);
  }
  std::printf("  firmware: %llu samples, %llu missed ticks, %d undecodable frames\n",
              static_cast<unsigned long long>(f.samples_fed), static_cast<unsigned long long>(f.missed_ticks),
              f.heard.undecodable);
}

// The switches after the initial one (the pole's first sighting) decided before the crossing.
std::vector<gs::estimation::ModeSwitch> in_flight_switches(const Flight& f) {
  std::vector<gs::estimation::ModeSwitch> out;
  for (std::size_t i = 1; i < f.switches.size(); ++i) {
    if (f.switches[i].detected_t_s - kSettle_s < *f.crossing_t_s) out.push_back(f.switches[i]);
  }
  return out;
}

}  // namespace

TEST_CASE("the throw through the real firmware: armed, balanced, tracked to T, released at T, "
          "no impact report",
          "[estimation][hil][sil][throw]") {
  const Flight& f = the_flight();
  print_flight(f);
  const gs::planning::ThrowProblem problem;
  const double T = problem.duration_s;

  // The protocol's arm sequence is accepted in the air, the take-off setpoint takes the
  // firmware to `flying`, and it stays there to the end (no failsafe, no KILL latch from a
  // crash report): every setpoint arrived fresh and every tick was answered.
  REQUIRE(f.heard.arm_ack);
  CHECK(f.heard.arm_ack->result == proto::AckResult::accepted);
  CHECK(f.flying_throughout);
  CHECK(f.missed_ticks == 0);
  CHECK(f.samples_fed == static_cast<std::uint64_t>(std::lround((kSettle_s + T + 1.6) / 1e-3)));
  CHECK(f.heard.undecodable == 0);

  // The settling hover. The balancing LQR through the firmware holds the pole within 0.2 mrad
  // and the plate within 5 mm of the plan's origin (measured); 5 mrad and 2 cm are a fraction of
  // the throw's own tolerances (0.02 rad, 5 cm in throw_tracking.hpp) and fail for a hover that
  // does not balance (the upright pole diverges at 3.3/s) or drifts.
  CHECK(f.settle_tilt_max_rad < 0.005);
  CHECK(std::hypot(f.start_state(planar::kX), f.start_state(planar::kZ)) < 0.02);

  // RATE_THRUST's quantisation: half a bit, 1 mrad/s and 0.005 m/s^2, three orders below the
  // TV-LQR's input tolerances (2 rad/s, 2 m/s^2): not a cause of anything below.
  CHECK(f.max_rate_quantisation_radps <= 0.001 + 1e-6);
  CHECK(f.max_thrust_quantisation_mps2 <= 0.005 + 1e-6);

  // Tracking up to 0.3 s before T. Measured through the firmware: 0.012 rad of pole tilt, 5 cm
  // of position (the plate runs some 1-4 cm behind in x and 1-3 cm low in z: the firmware's
  // thrust does not carry the pole's contact force and the plant's drag, 5 % and 0.2 m/s^2 per
  // m/s, which the plan's model leaves out, and the stand-in meets the same), 0.046 rad of pitch
  // (the rate loop's lag behind a pitch rate that ramps to -1 rad/s; the stand-in's is the
  // same, 0.047 rad at t = 2.2 s). The stand-in keeps the tilt within 0.012 rad over the whole
  // throw. 0.03 rad, 8 cm, 0.08 rad bound them
  // with room and fail for a loop that does not follow the plan.
  CHECK(f.tracked_tilt_error_rad < 0.03);
  CHECK(f.tracked_position_error_m < 0.08);
  CHECK(f.tracked_pitch_error_rad < 0.08);
  // ... and to T, with the pole balanced across the throw's plane as well (see the flight loop):
  // measured 0.012 rad of tilt (the stand-in's figure), 0.079 rad of pitch as the plan's pitch
  // rate swings from -2.9 to +2.5 rad/s in the last 0.1 s.
  CHECK(f.max_tilt_error_rad < 0.03);
  CHECK(f.max_pitch_error_rad < 0.15);

  // The release: the plate's force on the pole vanishes after T. Measured T + 71 ms (the
  // stand-in: T + 47 ms): the release is soft, the normal force fading as the thrust falls
  // through the motors' 30 ms lag, which the stand-in's lead shortens and the firmware does not.
  REQUIRE(f.release_t_s);
  CHECK(*f.release_t_s > T - 0.01);
  CHECK(*f.release_t_s < T + 0.1);

  // The firmware's impact detector says nothing during the throw: its residual is the specific
  // force minus the commanded thrust through the motor lag, and the manoeuvre's thrust (1-18.6
  // m/s^2) and rates follow the commands through that lag; the pole's normal force is at most
  // 0.03 kg x 20 m/s^2 / 0.61 kg, 1 m/s^2 of the 6 m/s^2 trigger, so its loss at the release is
  // not an impact either. Measured: no IMPACT frame in the whole flight.
  for (const auto& [t, impact] : f.heard.impacts) {
    const double onset = impact.vehicle_time_us * 1e-6 - kSettle_s;
    CHECK_FALSE((onset > 0.0 && onset < *f.crossing_t_s));
    CHECK(impact.classification != proto::ImpactClass::crash);
  }

  // The estimator calls the launch by the plate's normal force at T + 13 ms (measured; decided at
  // T + 15 ms), before the soft release has quite ended. Since the vehicle checks each frame's
  // AUTH over two more ticks (docs/security.md) the release acts 2 ms later, the plate meets the
  // pole once more at T + 80 ms, and the estimator follows: back on the plate by innovation, then
  // free again by the normal force 3 ms later (measured). Before the link was authenticated it
  // kept the first call. The last call is the launch, by the normal force.
  const std::vector<gs::estimation::ModeSwitch> in_flight = in_flight_switches(f);
  REQUIRE(!in_flight.empty());
  CHECK(in_flight.size() <= 3);
  CHECK(in_flight.back().to == gs::estimation::PoleMode::free);
  CHECK(in_flight.back().reason == gs::estimation::SwitchReason::contact_force);
  CHECK(in_flight.front().to == gs::estimation::PoleMode::free);
  CHECK(in_flight.front().reason == gs::estimation::SwitchReason::contact_force);
  CHECK(in_flight.front().event_t_s - kSettle_s >= T - 1e-9);

  // The catch point predicted from the estimate against where the plant's pole comes down:
  // measured 95 mm 0.1 s after the release and 0.3 mm 0.15 s before the crossing. The early
  // figure is the price of the single early call: the free flight is seeded while the pole still
  // rides the plate for a few frames (the double call re-seeded it later and measured 28 mm); the
  // closed loop re-plans the catch at every frame and catches on the late figure.
  CHECK(f.catch_error_m < 0.15);
  CHECK(f.catch_error_late_m < 0.02);
}
