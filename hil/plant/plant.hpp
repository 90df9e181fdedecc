// The truth plant: two quadrocopters and a pole in 3D, the world the firmware and the ground
// station are tested against. It is written apart from groundstation/model and has more physics
// than the paper's models (Section II):
//
//  - each vehicle is a rigid body with its inertia, driven by four motors whose thrust follows
//    the command through a first-order lag, within [0, gain * thrust_max], with per-motor gain
//    mismatch, rotor drag torque about z and a linear translational drag; each vehicle's mass,
//    inertia, thrust and motor lag may differ from the airframe's (VehicleConfig's scales), and
//    with battery_enabled its battery sags and drains and its motors' thrust goes with the
//    square of its voltage (battery.hpp);
//  - the pole is a rigid rod in 3D (6 DoF: transverse inertia m (L^2/3 + r^2/2), axial m r^2)
//    with the paper's drag law integrated along its length (pole_drag.hpp);
//  - each pole end touches each vehicle's catching plate (a disc of plate_radius_m at
//    plate_height_m above the CG, normal along body z) and the floor through a compliant contact
//    with stick-slip friction (contact_law.hpp); the reaction acts on the vehicle at the contact
//    point, so its IMU feels it. A pole end that slides past the rim loses the plate; an end can
//    only land on a plate from above. (Not modelled: the pole's shaft touching a vehicle, and
//    the vehicles touching each other.)
//  - each vehicle rests on the floor on four feet under its motors;
//  - an IMU per vehicle (imu.hpp) and the motion capture (mocap.hpp).
//
// Time is the plant's own: step() advances it; nothing reads a clock. The integration is RK4
// with a step of integration_step_free_s, shortened while a pole end touches something or is
// about to (a vehicle's feet on the floor are not stiff at the free step), and cut at every
// sensor sample so that samples fall on their exact times. The short step is
// integration_step_contact_s for the stiffest contact, an end pushed across the pole (effective
// mass about m/4), and for every end arriving at a surface; with
// integration_contact_step_by_mass, an end in a contact that is slower (an upright pole on a
// plate: effective mass about m) gets a step longer by the ratio of the two contact rates, so that step times rate stays at the reference's, never longer than the free
// step; the steps within a sample period are made equal. A run is fully determined by the
// configuration and the seed.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <vector>

#include "hil/plant/battery.hpp"
#include "hil/plant/contact_law.hpp"
#include "hil/plant/imu.hpp"
#include "hil/plant/mocap.hpp"
#include "hil/plant/motor.hpp"
#include "hil/plant/plant_config.hpp"
#include "hil/plant/types.hpp"
#include "pa/vehicle_id.hpp"

namespace hil {

// A pole end starting or ending contact with a surface.
struct PoleContactEvent {
  double t_s = 0.0;
  int end = 0;  // 0 or 1 (PoleState::end_m)
  Surface surface = Surface::floor;
  bool begins = true;
};

class Plant {
 public:
  // `config` is used as given (randomise it first with randomised() if wanted); `seed` draws the
  // IMU biases and all sensor noise. The vehicles start parked on the floor at x = -1 m and
  // x = +1 m and the pole lies still on the floor between them, along y; set_*() put them
  // elsewhere.
  // Throws std::invalid_argument if check_plant_config() reports a problem.
  explicit Plant(const PlantConfig& config, std::uint64_t seed = 1);

  const PlantConfig& config() const { return config_; }
  double t_s() const { return static_cast<double>(t_ns_) * 1e-9; }

  // Replace a vehicle's state. Contacts of the moved body are
  // re-evaluated from scratch: a point placed up to 5 mm inside a surface rests on it (sticking
  // where it is); one placed deeper does not engage it at all. A state with a non-finite value
  // (or a zero quaternion) throws std::invalid_argument and changes nothing.
  void set_vehicle(pa::VehicleId vehicle, const VehicleState& state);
  void set_pole(const PoleState& state);
  // The pole put upright on `vehicle`'s plate, moving with it: a person handing it up.
  void place_pole_on(pa::VehicleId vehicle);
  // The pole taken off whatever holds it and laid still on the floor, its centre below
  // `centre_xy_m` and its axis along y: a person taking it down.
  void lay_pole_on_floor(const Vec3& centre_xy_m);

  // Advances by dt_s (rounded to whole nanoseconds; non-finite or negative does nothing) with
  // the motor commands held over the interval.
  void step(double dt_s, const MotorCommands& vehicle1, const MotorCommands& vehicle2);

  const VehicleState& vehicle(pa::VehicleId vehicle) const { return vehicles_[slot(vehicle)]; }
  const PoleState& pole() const { return pole_; }

  // --- contacts ---------------------------------------------------------------------------
  // What pole end `end` touches now (a plate before the floor).
  Contact pole_end_contact(int end) const;
  // What the pole touches: vehicle1, then vehicle2, then the floor, else none.
  Contact pole_contact() const;
  // The contact force on pole end `end` from `surface`, averaged over the last integration
  // step (inertial frame; the surface received the opposite).
  Vec3 pole_end_force_N(int end, Surface surface) const;
  bool vehicle_on_floor(pa::VehicleId vehicle) const;
  // A pole lying still on the floor (both ends on it, speed below 1 mm/s and tumbling rate below
  // 0.01 rad/s for 0.2 s) is put to sleep: it keeps its place (a spin about its own axis, which
  // nothing damps, is dropped) and costs no short steps until set_pole() moves it. Nothing else
  // in the plant can push it (see the list above).
  bool pole_asleep() const { return pole_asleep_; }
  // Pole contact changes since the last call, oldest first.
  std::vector<PoleContactEvent> take_contact_events();

  // --- sensors ------------------------------------------------------------------------------
  // The next IMU sample of `vehicle` not yet taken, oldest first. Samples are produced at
  // imu_rate_Hz; at most kImuQueueLimit are kept.
  bool pop_imu(pa::VehicleId vehicle, ImuSample& out);
  const ImuSample& latest_imu(pa::VehicleId vehicle) const { return latest_imu_[slot(vehicle)]; }
  // Whether the configured losses (the radios' and the motion capture's dropouts) apply now:
  // always, or with losses_only_in_pole_flight while the pole touches nothing.
  bool losses_active() const;
  // The next motion-capture frame delivered by now (capture time + latency <= t_s()).
  bool pop_mocap(CapturedFrame& out) { return mocap_.pop(t_s(), out); }
  static constexpr std::size_t kImuQueueLimit = 100000;

  // --- truth diagnostics (noise-free) -------------------------------------------------------
  // The specific force (body frame) and body rate of a vehicle averaged over the last
  // integration step: what a perfect IMU would read.
  const Vec3& true_specific_force_mps2(pa::VehicleId vehicle) const {
    return true_specific_force_[slot(vehicle)];
  }
  double pole_energy_J() const;                          // kinetic + potential (zero at z = 0)
  double vehicle_energy_J(pa::VehicleId vehicle) const;  // idem
  Vec3 pole_momentum_Ns() const;
  Vec3 vehicle_momentum_Ns(pa::VehicleId vehicle) const;
  Vec3 pole_angular_momentum_Nms(const Vec3& about_m) const;
  Vec3 vehicle_angular_momentum_Nms(pa::VehicleId vehicle, const Vec3& about_m) const;
  double pole_transverse_inertia_kgm2() const;
  double pole_axial_inertia_kgm2() const;
  const ImuModel& imu_model(pa::VehicleId vehicle) const { return imu_[slot(vehicle)]; }

  // --- state builders -----------------------------------------------------------------------
  // A vehicle at `position_m`, level, with heading `yaw_rad`, at rest, each motor producing a
  // quarter of `vehicle`'s weight.
  VehicleState hovering_vehicle(const Vec3& position_m, double yaw_rad,
                                pa::VehicleId vehicle = pa::kVehicle1) const;
  // A vehicle at rest on its feet on the floor (sunk by `vehicle`'s weight), motors stopped.
  VehicleState parked_vehicle(double x_m, double y_m, double yaw_rad,
                              pa::VehicleId vehicle = pa::kVehicle1) const;
  // The commands that hold every motor of `vehicle` at a quarter of the vehicle's weight with
  // this plant's motor gains and its battery's voltage now (an oracle: a real controller does
  // not know them).
  MotorCommands hover_commands(pa::VehicleId vehicle) const;
  // The thrust gain a ground station should measure of `vehicle` (an oracle, for tests and
  // printouts): the collective it commands for a hover (the airframe file's weight) over the
  // collective that holds the vehicle as built. The firmware takes the pack's sag out of its
  // commands (fw/battery_compensation.hpp), so the gain is the motors', propellers' and mass's
  // alone: the hover commands at the battery's voltage now, scaled back to the reference voltage.
  double true_thrust_gain(pa::VehicleId vehicle) const;
  // `vehicle`'s mass and principal inertia as built (the airframe's times its scales).
  double vehicle_mass_kg(pa::VehicleId vehicle) const { return vehicle_mass_kg_[slot(vehicle)]; }
  const Vec3& vehicle_inertia_kgm2(pa::VehicleId vehicle) const {
    return vehicle_inertia_kgm2_[slot(vehicle)];
  }
  // `vehicle`'s battery as of the last step (with battery_enabled; otherwise at its start,
  // unloaded).
  const BatteryState& battery(pa::VehicleId vehicle) const { return battery_[slot(vehicle)]; }
  // A full pack in place of `vehicle`'s (a person swapped it while the vehicle stood on the floor).
  void swap_battery(pa::VehicleId vehicle);
  // The plate's centre (on its surface) and normal, inertial frame.
  Vec3 plate_centre_m(pa::VehicleId vehicle) const;
  Vec3 plate_normal(pa::VehicleId vehicle) const;

  // A pole with centre `centre_m`, axis `axis` (normalised here), centre velocity `velocity_mps`
  // and angular velocity `rate_radps` (inertial frame; its component along the axis is the spin).
  static PoleState make_pole(const Vec3& centre_m, const Vec3& axis, const Vec3& velocity_mps,
                             const Vec3& rate_radps);

 private:
  // The pole lying still on the floor below `centre_xy_m`, along y.
  PoleState pole_on_floor(const Vec3& centre_xy_m) const;
  // The contact pairs: pole end e with surface s at e * 3 + s; vehicle v's foot f with the floor
  // at 6 + 4 v + f.
  static constexpr int kPolePairs = 6;
  static constexpr int kPairs = 14;
  struct PairMemory {
    bool engaged = false;
    bool above_at_start = false;  // the point was on the outer side of the surface when the step began
    bool anchored = false;
    Vec3 anchor = Vec3::Zero();   // plates: vehicle body frame relative to the CG; floor: inertial
    Vec3 force_N = Vec3::Zero();  // on the point, averaged over the last step
  };
  struct Bodies {
    std::array<RigidBodyState, 2> vehicle;
    RigidBodyState pole;
  };
  // (Not zeroed by construction, as Eigen's vectors are not: evaluate() sets every member.)
  struct BodyRate {
    Vec3 dp;
    Vec3 dv;
    Eigen::Vector4d dq;
    Vec3 dw;
  };
  struct Evaluation {
    std::array<BodyRate, 2> vehicle;
    BodyRate pole;
    std::array<Vec3, 2> specific_force_body;  // vehicles, body frame; always set by evaluate()
    // On the point, inertial; set by evaluate() for the step's candidate pairs only (Eigen
    // vectors are not zeroed by default construction).
    std::array<Vec3, kPairs> pair_force;
  };
  struct PairGeometry {
    Vec3 point_m;
    Vec3 normal;
    double gap_m;                // signed distance from the surface along the normal (> 0 outside)
    bool within_rim;             // plates: the point projects inside the disc
    Vec3 relative_velocity_mps;  // point relative to the surface material at the point
    Vec3 lever_vehicle_m;        // plates: point relative to the vehicle's CG (inertial)
  };

  // What every contact needs, computed once per evaluation: rotations, inertial rates, plate
  // centres, and the contact points (pole ends 0 and 1, then vehicle v's foot f at 2 + 4 v + f)
  // with their levers from their body's centre (inertial). A point's velocity is computed only
  // where it touches or may (geometry()).
  struct Kinematics {
    std::array<Mat3, 2> vehicle_rotation;
    std::array<Vec3, 2> vehicle_rate;
    std::array<Vec3, 2> plate_centre;
    std::array<Vec3, 10> point;
    std::array<Vec3, 10> lever;
    Mat3 pole_rotation;
    Vec3 pole_rate;
    // How far each vehicle's centre is above the floor beyond the reach of its feet: a lower
    // bound of its feet's gaps. Where it is positive (feet_clear) no foot can touch the floor,
    // and their points and levers are not computed here (gap_m() gives the bound).
    std::array<double, 2> feet_clearance_m;
    std::array<bool, 2> feet_clear;
  };
  // The rotors' wrench on each vehicle at the three times an RK4 step evaluates (its start, its
  // middle and its end: the thrusts follow their lags in closed form, so they are computed once
  // per step, not per evaluation).
  using RotorWrenches = std::array<BodyWrench, 2>;

  // The vehicle's slot in the per-vehicle arrays; std::invalid_argument for a vehicle the act
  // does not fly. Inline: every accessor on the arena's per-step path goes through it.
  static std::size_t slot(pa::VehicleId vehicle) {
    if (!pa::is_act_vehicle(vehicle)) [[unlikely]]
      throw_no_vehicle(vehicle);
    return pa::act_slot(vehicle);
  }
  [[noreturn]] static void throw_no_vehicle(pa::VehicleId vehicle);
  Kinematics kinematics(const Bodies& b) const;
  const ContactLaw& law(Surface surface) const { return surface == Surface::floor ? floor_law_ : plate_law_; }
  static Surface pair_surface(int pair) {
    return pair < kPolePairs ? static_cast<Surface>(pair % 3) : Surface::floor;
  }
  static int pair_point(int pair) { return pair < kPolePairs ? pair / 3 : 2 + (pair - kPolePairs); }
  // Contact point `point` (numbered as in Kinematics) and its lever from its body's centre.
  void point_and_lever(const Bodies& b, const Kinematics& k, int point, Vec3& point_m, Vec3& lever_m) const;
  // The signed distance of pair `pair`'s point from its surface along the normal (> 0 outside):
  // the first question about every pair, and most need no other (geometry() has it too).
  inline double gap_m(const Kinematics& k, int pair) const;  // (plant.cpp, the only user)
  PairGeometry geometry(const Bodies& b, const Kinematics& k, int pair) const;
  Evaluation evaluate(const Bodies& b, const Kinematics& k, const RotorWrenches& rotors) const;
  static Bodies advance(const Bodies& b, const Evaluation& rate, double h_s);
  // The thrusts of vehicle v's motors after a step whose lag decay factor exp(-t / tau) is `decay`.
  std::array<double, 4> thrust_at(std::size_t v, double decay) const;
  std::int64_t choose_step_ns(std::int64_t limit_ns, const Bodies& b, const Kinematics& k) const;
  // The fastest rate (1/s) of pole pair `pair`'s contact at geometry `g`: the larger root of its
  // spring-damper on the pole end's effective mass (with the plate's vehicle), along the normal
  // and across it. With `worst_case`, the rate for the smallest effective mass of a pole end
  // alone, the case integration_step_contact_s is sized for.
  double contact_rate_per_s(int pair, const PairGeometry& g, const Vec3& pole_axis, bool worst_case) const;
  void substep(std::int64_t h_ns, const Bodies& b0, const Kinematics& k0);
  void update_contacts();
  void update_pole_rest(double h_s);
  void reset_pair(int pair);
  void reset_pairs_of_pole();
  void reset_pairs_of_vehicle(pa::VehicleId vehicle);
  // Each battery's voltage and current under the motors' thrust now (battery_enabled only).
  void load_batteries();
  void capture_mocap();
  void sample_imu();
  Bodies bodies() const;
  void store(const Bodies& b);

  PlantConfig config_;
  std::int64_t t_ns_ = 0;
  std::int64_t free_step_ns_;
  std::int64_t contact_step_ns_;
  std::int64_t imu_period_ns_;
  std::int64_t mocap_period_ns_;
  // Each foot relative to the CG, body frame (fixed by the configuration), and how far the
  // farthest is from the CG, with a margin for rounding.
  std::array<Vec3, 4> foot_body_m_;
  double foot_reach_m_ = 0.0;
  // The pairs the current step evaluates: those engaged or with their point outside the surface
  // when the step began (no other pair can touch during it), in order.
  std::array<std::uint8_t, kPairs> candidates_{};
  int candidate_count_ = 0;
  // The principal moments of inertia (body frame) of each vehicle and of the pole, and the
  // vehicles' masses, motor gains (with their thrust scales) and motor time constants.
  std::array<Vec3, 2> vehicle_inertia_kgm2_;
  Vec3 pole_inertia_kgm2_;
  std::array<double, 2> vehicle_mass_kg_{};
  std::array<std::array<double, 4>, 2> motor_gain_{};
  std::array<double, 2> motor_time_constant_s_{};
  // Their inverses and those of the masses: the rates multiply rather than divide.
  std::array<Vec3, 2> vehicle_inverse_inertia_;
  Vec3 pole_inverse_inertia_;
  std::array<double, 2> vehicle_inverse_mass_per_kg_{};
  double pole_inverse_mass_per_kg_ = 0.0;
  ContactLaw floor_law_;
  ContactLaw plate_law_;
  // contact_rate_per_s(worst case) of a pole end on the floor and on a plate.
  double worst_rate_floor_per_s_ = 0.0;
  double worst_rate_plate_per_s_ = 0.0;
  std::uint64_t imu_tick_ = 0;     // samples taken so far; the next is due at (tick + 1) periods
  std::uint64_t mocap_index_ = 0;  // frames captured so far; the next is due at index periods

  std::array<VehicleState, 2> vehicles_{};
  PoleState pole_{};
  std::array<std::array<double, 4>, 2> target_thrust_N_{};
  std::array<BatteryState, 2> battery_{};
  std::array<double, 2> charge_start_{1.0, 1.0};  // each pack's charge when it was put in
  std::array<PairMemory, kPairs> pairs_{};
  std::vector<PoleContactEvent> events_;
  bool pole_asleep_ = false;
  double pole_rest_s_ = 0.0;
  // The kinematics of the current state, while kinematics_valid_ (anything that moves a body
  // clears it).
  Kinematics kinematics_{};
  bool kinematics_valid_ = false;
  static constexpr double kRestSpeed_mps = 1e-3;
  static constexpr double kRestRate_radps = 1e-2;
  static constexpr double kRestTime_s = 0.2;

  std::array<ImuModel, 2> imu_;
  // Body-frame specific force and rate integrated since the last sample (zeroed in the constructor).
  std::array<Vec3, 2> imu_sum_force_;
  std::array<Vec3, 2> imu_sum_rate_;
  double imu_sum_time_s_ = 0.0;
  std::array<std::deque<ImuSample>, 2> imu_queue_;
  std::array<ImuSample, 2> latest_imu_{};
  std::array<Vec3, 2> true_specific_force_;
  MocapModel mocap_;
};

}  // namespace hil
