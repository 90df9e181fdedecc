#include "hil/plant/plant.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "hil/plant/motor.hpp"
#include "hil/plant/pole_drag.hpp"

namespace hil {

namespace {

// A point this close inside a surface when a step begins still counts as arriving from
// outside: it absorbs the rounding of states that were placed exactly on a surface.
constexpr double kPlacementTolerance_m = 1e-6;
// A body put down this far inside a surface (at most) is resting on it: see Plant::reset_pair.
constexpr double kPlacementDepth_m = 0.005;
// A contact is "near" (and the short step is used) within this distance plus two free steps of
// closing speed.
constexpr double kNearMargin_m = 0.002;

std::int64_t to_ns(double s) { return static_cast<std::int64_t>(std::llround(s * 1e9)); }

// R v, R^T v and the quaternion rate written out on scalars: GCC leaves Eigen's fixed-size
// products as calls at -O2, and these are on every evaluation's path.
inline Vec3 times(const Mat3& r, const Vec3& v) {
  return Vec3(r(0, 0) * v.x() + r(0, 1) * v.y() + r(0, 2) * v.z(),
              r(1, 0) * v.x() + r(1, 1) * v.y() + r(1, 2) * v.z(),
              r(2, 0) * v.x() + r(2, 1) * v.y() + r(2, 2) * v.z());
}
inline Vec3 transpose_times(const Mat3& r, const Vec3& v) {
  return Vec3(r(0, 0) * v.x() + r(1, 0) * v.y() + r(2, 0) * v.z(),
              r(0, 1) * v.x() + r(1, 1) * v.y() + r(2, 1) * v.z(),
              r(0, 2) * v.x() + r(1, 2) * v.y() + r(2, 2) * v.z());
}

inline Eigen::Vector4d quaternion_rate(const Quat& q, const Vec3& rate_body_radps) {
  // q' = q (0, omega) / 2 with omega in the body frame (coefficients x, y, z, w).
  const double wx = rate_body_radps.x(), wy = rate_body_radps.y(), wz = rate_body_radps.z();
  return Eigen::Vector4d(
      0.5 * (q.w() * wx + q.y() * wz - q.z() * wy), 0.5 * (q.w() * wy + q.z() * wx - q.x() * wz),
      0.5 * (q.w() * wz + q.x() * wy - q.y() * wx), -0.5 * (q.x() * wx + q.y() * wy + q.z() * wz));
}

}  // namespace

Plant::Plant(const PlantConfig& config, std::uint64_t seed)
    : config_(config),
      imu_{ImuModel(config.imu, seed, RandomStream::imu_vehicle1),
           ImuModel(config.imu, seed, RandomStream::imu_vehicle2)},
      mocap_(config.mocap, seed) {
  if (const std::string problem = check_plant_config(config); !problem.empty())
    throw std::invalid_argument(problem);
  free_step_ns_ = std::max<std::int64_t>(1, to_ns(config.integration.step_free_s));
  contact_step_ns_ = std::max<std::int64_t>(1, to_ns(config.integration.step_contact_s));
  imu_period_ns_ = std::max<std::int64_t>(1, to_ns(1.0 / config.imu.rate_Hz));
  mocap_period_ns_ = std::max<std::int64_t>(1, to_ns(1.0 / config.mocap.rate_Hz));
  for (int f = 0; f < 4; ++f)
    foot_body_m_[f] = motor_position_body_m(config.vehicle, f) - Vec3(0.0, 0.0, config.vehicle.foot_depth_m);
  for (const Vec3& foot : foot_body_m_) foot_reach_m_ = std::max(foot_reach_m_, foot.norm());
  foot_reach_m_ = foot_reach_m_ * (1.0 + 1e-9) + 1e-9;
  // (A scale of 1 multiplies exactly: the airframe's own values, bit for bit.)
  const VehicleConfig& vc = config.vehicle;
  for (int v = 0; v < 2; ++v) {
    vehicle_inertia_kgm2_[v] =
        Vec3(vc.inertia_xx_kgm2, vc.inertia_yy_kgm2, vc.inertia_zz_kgm2) * vc.inertia_scale[v];
    vehicle_inverse_inertia_[v] = vehicle_inertia_kgm2_[v].cwiseInverse();
    vehicle_mass_kg_[v] = vc.mass_kg * vc.mass_scale[v];
    vehicle_inverse_mass_per_kg_[v] = 1.0 / vehicle_mass_kg_[v];
    motor_time_constant_s_[v] = vc.motor_time_constant_s * vc.motor_time_constant_scale[v];
    for (int i = 0; i < 4; ++i) motor_gain_[v][i] = vc.motor_gain[v][i] * vc.thrust_scale[v];
    charge_start_[v] = config.battery.charge_start[v];
    battery_[v].state_of_charge = charge_start_[v];
    battery_[v].voltage_V = battery_open_circuit_V(config.battery, battery_[v].state_of_charge);
  }
  pole_inertia_kgm2_ =
      Vec3(pole_transverse_inertia_kgm2(), pole_transverse_inertia_kgm2(), pole_axial_inertia_kgm2());
  pole_inverse_inertia_ = pole_inertia_kgm2_.cwiseInverse();
  pole_inverse_mass_per_kg_ = 1.0 / config.pole.mass_kg;
  const ContactConfig& c = config.contact;
  floor_law_ =
      ContactLaw{c.floor_stiffness_Npm,          c.floor_damping_Nspm, c.floor_damping_force_max_N,
                 c.floor_rebound_damping_Nspm,   c.floor_friction,     c.floor_tangential_stiffness_Npm,
                 c.floor_tangential_damping_Nspm};
  plate_law_ =
      ContactLaw{c.plate_stiffness_Npm,          c.plate_damping_Nspm, c.plate_damping_force_max_N,
                 c.plate_rebound_damping_Nspm,   c.plate_friction,     c.plate_tangential_stiffness_Npm,
                 c.plate_tangential_damping_Nspm};
  const PairGeometry none{};
  worst_rate_floor_per_s_ = contact_rate_per_s(static_cast<int>(Surface::floor), none, Vec3::UnitZ(), true);
  worst_rate_plate_per_s_ = contact_rate_per_s(static_cast<int>(Surface::plate1), none, Vec3::UnitZ(), true);
  for (int v = 0; v < 2; ++v) {
    imu_sum_force_[v].setZero();
    imu_sum_rate_[v].setZero();
    true_specific_force_[v].setZero();
  }
  vehicles_[0] = parked_vehicle(-1.0, 0.0, 0.0, pa::kVehicle1);
  vehicles_[1] = parked_vehicle(1.0, 0.0, 0.0, pa::kVehicle2);
  pole_ = pole_on_floor(Vec3::Zero());
  for (int p = 0; p < kPairs; ++p) reset_pair(p);
  pole_asleep_ = true;
  events_.clear();
}

PoleState Plant::pole_on_floor(const Vec3& centre_xy_m) const {
  // Still on the floor, each end sunk by half its weight over the floor's stiffness.
  const double sink_m =
      config_.pole.mass_kg * config_.gravity_mps2 / (2.0 * config_.contact.floor_stiffness_Npm);
  return make_pole(Vec3(centre_xy_m.x(), centre_xy_m.y(), config_.contact.floor_height_m - sink_m),
                   Vec3::UnitY(), Vec3::Zero(), Vec3::Zero());
}

void Plant::lay_pole_on_floor(const Vec3& centre_xy_m) { set_pole(pole_on_floor(centre_xy_m)); }

// --- state builders ------------------------------------------------------------------------

PoleState Plant::make_pole(const Vec3& centre_m, const Vec3& axis, const Vec3& velocity_mps,
                           const Vec3& rate_radps) {
  PoleState p;
  p.body.position_m = centre_m;
  p.body.velocity_mps = velocity_mps;
  p.body.attitude = Quat::FromTwoVectors(Vec3::UnitZ(), axis.normalized());
  p.body.rate_body_radps = p.body.attitude.conjugate() * rate_radps;
  return p;
}

VehicleState Plant::hovering_vehicle(const Vec3& position_m, double yaw_rad, pa::VehicleId vehicle) const {
  VehicleState v;
  v.body.position_m = position_m;
  v.body.attitude = Quat(Eigen::AngleAxisd(yaw_rad, Vec3::UnitZ()));
  v.motor_thrust_N.fill(vehicle_mass_kg_[slot(vehicle)] * config_.gravity_mps2 / 4.0);
  return v;
}

VehicleState Plant::parked_vehicle(double x_m, double y_m, double yaw_rad, pa::VehicleId vehicle) const {
  VehicleState v;
  // Each foot sunk by a quarter of the weight over the floor's stiffness: at rest from the start.
  const double sink_m =
      vehicle_mass_kg_[slot(vehicle)] * config_.gravity_mps2 / (4.0 * config_.contact.floor_stiffness_Npm);
  v.body.position_m = Vec3(x_m, y_m, config_.contact.floor_height_m + config_.vehicle.foot_depth_m - sink_m);
  v.body.attitude = Quat(Eigen::AngleAxisd(yaw_rad, Vec3::UnitZ()));
  return v;
}

MotorCommands Plant::hover_commands(pa::VehicleId vehicle) const {
  MotorCommands c;
  const std::size_t v = slot(vehicle);
  const double per_motor_N = vehicle_mass_kg_[v] * config_.gravity_mps2 / 4.0;
  for (int i = 0; i < 4; ++i) {
    c.command[i] = per_motor_N / (motor_gain_[v][i] * config_.vehicle.motor_thrust_max_N);
    if (config_.battery.enabled != 0)
      c.command[i] /= thrust_voltage_factor(battery_[v].voltage_V, config_.battery.reference_voltage_V);
  }
  return c;
}

double Plant::true_thrust_gain(pa::VehicleId vehicle) const {
  // The hover commands at the reference voltage: the airframe file's weight over the vehicle's,
  // over the mean of the inverse motor gains (each motor holds a quarter of the weight).
  const std::size_t v = slot(vehicle);
  double inverse_gains = 0.0;
  for (int i = 0; i < 4; ++i) inverse_gains += 0.25 / motor_gain_[v][i];
  return config_.vehicle.mass_kg / (vehicle_mass_kg_[v] * inverse_gains);
}

Vec3 Plant::plate_centre_m(pa::VehicleId vehicle) const {
  const RigidBodyState& b = vehicles_[slot(vehicle)].body;
  return b.position_m + b.attitude * Vec3(0.0, 0.0, config_.vehicle.plate_height_m);
}

Vec3 Plant::plate_normal(pa::VehicleId vehicle) const {
  return vehicles_[slot(vehicle)].body.attitude * Vec3::UnitZ();
}

namespace {
bool finite(const RigidBodyState& b) {
  return b.position_m.allFinite() && b.velocity_mps.allFinite() && b.attitude.coeffs().allFinite() &&
         b.attitude.norm() > 0.5 && b.rate_body_radps.allFinite();
}
}  // namespace

void Plant::set_vehicle(pa::VehicleId vehicle, const VehicleState& state) {
  if (!finite(state.body)) throw std::invalid_argument("Plant::set_vehicle: the state is not finite");
  VehicleState& v = vehicles_[slot(vehicle)];
  kinematics_valid_ = false;
  v = state;
  v.body.attitude.normalize();
  for (double& f : v.motor_thrust_N) f = std::isfinite(f) ? std::max(0.0, f) : 0.0;
  reset_pairs_of_vehicle(vehicle);
}

void Plant::place_pole_on(pa::VehicleId vehicle) {
  // End 0 on the plate, the pole upright.
  const double above_plate_m = -config_.pole.end_along_axis_m(0);
  set_pole(make_pole(plate_centre_m(vehicle) + above_plate_m * Vec3::UnitZ(), Vec3::UnitZ(),
                     this->vehicle(vehicle).body.velocity_mps, Vec3::Zero()));
}

void Plant::set_pole(const PoleState& state) {
  if (!finite(state.body)) throw std::invalid_argument("Plant::set_pole: the state is not finite");
  kinematics_valid_ = false;
  pole_ = state;
  pole_.body.attitude.normalize();
  pole_asleep_ = false;
  pole_rest_s_ = 0.0;
  reset_pairs_of_pole();
}

void Plant::reset_pair(int pair) {
  PairMemory& m = pairs_[pair];
  const bool was = m.engaged;
  m = PairMemory{};
  // A point placed just inside a surface (a body put down resting on it) is in contact; one
  // placed deeper is not (it cannot have got there from outside).
  const Bodies b = bodies();
  const PairGeometry g = geometry(b, kinematics(b), pair);
  if (g.gap_m < 0.0 && g.gap_m >= -kPlacementDepth_m && g.within_rim) {
    m.engaged = true;
    m.anchored = true;
    const Vec3 on_surface = g.point_m - g.gap_m * g.normal;
    const Surface surface = pair_surface(pair);
    if (surface == Surface::floor) {
      m.anchor = on_surface;
    } else {
      const RigidBodyState& body = b.vehicle[surface == Surface::plate1 ? 0 : 1];
      m.anchor = body.attitude.conjugate() * (on_surface - body.position_m);
    }
  }
  if (pair < kPolePairs && was != m.engaged) {
    events_.push_back(PoleContactEvent{t_s(), pair / 3, pair_surface(pair), m.engaged});
  }
}

void Plant::throw_no_vehicle(pa::VehicleId vehicle) {
  throw std::invalid_argument("Plant: no vehicle with node " + std::to_string(vehicle.node()));
}

void Plant::reset_pairs_of_pole() {
  for (int p = 0; p < kPolePairs; ++p) reset_pair(p);
}

void Plant::reset_pairs_of_vehicle(pa::VehicleId vehicle) {
  const int v = static_cast<int>(slot(vehicle));
  const Surface plate = v == 0 ? Surface::plate1 : Surface::plate2;
  for (int p = 0; p < kPolePairs; ++p) {
    if (pair_surface(p) == plate) reset_pair(p);
  }
  for (int f = 0; f < 4; ++f) reset_pair(kPolePairs + 4 * v + f);
}

// --- contacts --------------------------------------------------------------------------------

Plant::Kinematics Plant::kinematics(const Bodies& b) const {
  Kinematics k;
  const VehicleConfig& vc = config_.vehicle;
  for (int v = 0; v < 2; ++v) {
    const RigidBodyState& body = b.vehicle[v];
    k.vehicle_rotation[v] = body.attitude.toRotationMatrix();
    k.vehicle_rate[v] = times(k.vehicle_rotation[v], body.rate_body_radps);
    k.plate_centre[v] = body.position_m + vc.plate_height_m * k.vehicle_rotation[v].col(2);
    k.feet_clearance_m[v] = body.position_m.z() - foot_reach_m_ - config_.contact.floor_height_m;
    k.feet_clear[v] = k.feet_clearance_m[v] > 0.0;
    if (k.feet_clear[v]) continue;
    for (int f = 0; f < 4; ++f) {
      const Vec3 r = times(k.vehicle_rotation[v], foot_body_m_[f]);
      k.point[2 + 4 * v + f] = body.position_m + r;
      k.lever[2 + 4 * v + f] = r;
    }
  }
  const RigidBodyState& pole = b.pole;
  k.pole_rotation = pole.attitude.toRotationMatrix();
  k.pole_rate = times(k.pole_rotation, pole.rate_body_radps);
  for (int e = 0; e < 2; ++e) {
    const Vec3 r = config_.pole.end_along_axis_m(e) * k.pole_rotation.col(2);
    k.point[e] = pole.position_m + r;
    k.lever[e] = r;
  }
  return k;
}

void Plant::point_and_lever(const Bodies& b, const Kinematics& k, int point, Vec3& point_m,
                            Vec3& lever_m) const {
  if (point >= 2 && k.feet_clear[(point - 2) / 4]) {
    const int v = (point - 2) / 4;
    lever_m = times(k.vehicle_rotation[v], foot_body_m_[(point - 2) % 4]);
    point_m = b.vehicle[v].position_m + lever_m;
    return;
  }
  point_m = k.point[point];
  lever_m = k.lever[point];
}

inline double Plant::gap_m(const Kinematics& k, int pair) const {
  if (pair >= kPolePairs) {
    const int v = (pair - kPolePairs) / 4;
    // (The foot's height is the CG's less at most the reach.)
    if (k.feet_clear[v]) return k.feet_clearance_m[v];
  }
  const Vec3& point = k.point[pair_point(pair)];
  const Surface surface = pair_surface(pair);
  if (surface == Surface::floor) return point.z() - config_.contact.floor_height_m;
  const int v = surface == Surface::plate1 ? 0 : 1;
  return (point - k.plate_centre[v]).dot(k.vehicle_rotation[v].col(2));
}

Plant::PairGeometry Plant::geometry(const Bodies& b, const Kinematics& k, int pair) const {
  PairGeometry g;
  const int point = pair_point(pair);
  Vec3 lever;
  point_and_lever(b, k, point, g.point_m, lever);
  const Vec3 point_velocity =
      point < 2
          ? Vec3(b.pole.velocity_mps + k.pole_rate.cross(lever))
          : Vec3(b.vehicle[(point - 2) / 4].velocity_mps + k.vehicle_rate[(point - 2) / 4].cross(lever));
  const Surface surface = pair_surface(pair);
  if (surface == Surface::floor) {
    g.normal = Vec3::UnitZ();
    g.gap_m = g.point_m.z() - config_.contact.floor_height_m;
    g.within_rim = true;
    g.relative_velocity_mps = point_velocity;
    g.lever_vehicle_m = Vec3::Zero();
  } else {
    const int v = surface == Surface::plate1 ? 0 : 1;
    g.normal = k.vehicle_rotation[v].col(2);
    const Vec3 d = g.point_m - k.plate_centre[v];
    g.gap_m = d.dot(g.normal);
    g.within_rim = (d - g.gap_m * g.normal).squaredNorm() <=
                   config_.vehicle.plate_radius_m * config_.vehicle.plate_radius_m;
    g.lever_vehicle_m = g.point_m - b.vehicle[v].position_m;
    g.relative_velocity_mps =
        point_velocity - (b.vehicle[v].velocity_mps + k.vehicle_rate[v].cross(g.lever_vehicle_m));
  }
  return g;
}

// --- dynamics --------------------------------------------------------------------------------

std::array<double, 4> Plant::thrust_at(std::size_t v, double decay) const {
  // motor_thrust_after_N() for each motor, with the lag's decay (one exp) shared by all.
  std::array<double, 4> f{};
  for (int i = 0; i < 4; ++i) {
    f[i] = target_thrust_N_[v][i] + (vehicles_[v].motor_thrust_N[i] - target_thrust_N_[v][i]) * decay;
  }
  return f;
}

Plant::Evaluation Plant::evaluate(const Bodies& b, const Kinematics& k, const RotorWrenches& rotors) const {
  Evaluation e;
  const Vec3 gravity(0.0, 0.0, -config_.gravity_mps2);
  const VehicleConfig& vc = config_.vehicle;

  std::array<Vec3, 2> vehicle_force;        // non-gravitational, inertial
  std::array<Vec3, 2> vehicle_torque_body;  // about the CG
  for (int v = 0; v < 2; ++v) {
    const RigidBodyState& body = b.vehicle[v];
    vehicle_force[v] = times(k.vehicle_rotation[v], rotors[v].force_N) - vc.drag_Nspm * body.velocity_mps;
    vehicle_torque_body[v] = rotors[v].torque_Nm;
  }

  const RigidBodyState& pole = b.pole;
  Vec3 pole_force = Vec3::Zero();
  Vec3 pole_torque = Vec3::Zero();  // inertial
  if (!pole_asleep_) {              // (asleep, it is still: no drag)
    const Wrench drag = pole_drag(config_.pole, pole.velocity_mps, k.pole_rate, k.pole_rotation.col(2));
    pole_force = drag.force_N;
    pole_torque = drag.torque_Nm;
  }

  for (int i = 0; i < candidate_count_; ++i) {
    const int p = candidates_[i];
    const PairMemory& m = pairs_[p];
    e.pair_force[p].setZero();
    if (!(gap_m(k, p) < 0.0)) continue;
    const PairGeometry g = geometry(b, k, p);
    if (!g.within_rim) continue;
    const Surface surface = pair_surface(p);
    Vec3 offset = Vec3::Zero();
    if (m.anchored) {
      const int v = surface == Surface::plate1 ? 0 : 1;
      const Vec3 anchor = surface == Surface::floor
                              ? m.anchor
                              : Vec3(b.vehicle[v].position_m + times(k.vehicle_rotation[v], m.anchor));
      offset = g.point_m - anchor;
    }
    const Vec3 f = contact_force_N(law(surface), g.normal, -g.gap_m, g.relative_velocity_mps, offset);
    e.pair_force[p] = f;
    // The point's body takes f, the surface's body -f, both at the contact point.
    if (p < kPolePairs) {
      pole_force += f;
      pole_torque += (g.point_m - pole.position_m).cross(f);
    } else {
      const int v = (p - kPolePairs) / 4;
      vehicle_force[v] += f;
      vehicle_torque_body[v] +=
          transpose_times(k.vehicle_rotation[v], (g.point_m - b.vehicle[v].position_m).cross(f));
    }
    if (surface != Surface::floor) {
      const int v = surface == Surface::plate1 ? 0 : 1;
      vehicle_force[v] -= f;
      vehicle_torque_body[v] -= transpose_times(k.vehicle_rotation[v], g.lever_vehicle_m.cross(f));
    }
  }

  for (int v = 0; v < 2; ++v) {
    const RigidBodyState& body = b.vehicle[v];
    BodyRate& r = e.vehicle[v];
    r.dp = body.velocity_mps;
    const Vec3 specific_force = vehicle_force[v] * vehicle_inverse_mass_per_kg_[v];
    r.dv = specific_force + gravity;
    r.dq = quaternion_rate(body.attitude, body.rate_body_radps);
    const Vec3 w = body.rate_body_radps;
    r.dw = (vehicle_torque_body[v] - w.cross(vehicle_inertia_kgm2_[v].cwiseProduct(w)))
               .cwiseProduct(vehicle_inverse_inertia_[v]);
    e.specific_force_body[v] = transpose_times(k.vehicle_rotation[v], specific_force);
  }
  BodyRate& r = e.pole;
  if (pole_asleep_) {  // (asleep, the pole keeps its place: all rates stay zero)
    r.dp.setZero();
    r.dv.setZero();
    r.dq.setZero();
    r.dw.setZero();
    return e;
  }
  const Vec3& inertia = pole_inertia_kgm2_;
  r.dp = pole.velocity_mps;
  r.dv = pole_force * pole_inverse_mass_per_kg_ + gravity;
  r.dq = quaternion_rate(pole.attitude, pole.rate_body_radps);
  const Vec3 w = pole.rate_body_radps;
  const Vec3 torque_body = transpose_times(k.pole_rotation, pole_torque);
  r.dw = (torque_body - w.cross(inertia.cwiseProduct(w))).cwiseProduct(pole_inverse_inertia_);
  return e;
}

Plant::Bodies Plant::advance(const Bodies& b, const Evaluation& rate, double h_s) {
  auto move = [h_s](RigidBodyState s, const BodyRate& r) {
    s.position_m += h_s * r.dp;
    s.velocity_mps += h_s * r.dv;
    s.attitude.coeffs() += h_s * r.dq;
    s.attitude.coeffs() *= 1.0 / s.attitude.coeffs().norm();
    s.rate_body_radps += h_s * r.dw;
    return s;
  };
  Bodies out;
  for (int v = 0; v < 2; ++v) out.vehicle[v] = move(b.vehicle[v], rate.vehicle[v]);
  out.pole = move(b.pole, rate.pole);
  return out;
}

Plant::Bodies Plant::bodies() const {
  Bodies b;
  for (int v = 0; v < 2; ++v) b.vehicle[v] = vehicles_[v].body;
  b.pole = pole_.body;
  return b;
}

void Plant::store(const Bodies& b) {
  for (int v = 0; v < 2; ++v) vehicles_[v].body = b.vehicle[v];
  pole_.body = b.pole;
}

namespace {
// The larger magnitude of the roots of s^2 + (c/m) s + k/m: how fast a spring-damper on mass m
// moves (the step must resolve it).
double fastest_root_per_s(double stiffness_Npm, double damping_Nspm, double inverse_mass_per_kg) {
  const double b = damping_Nspm * inverse_mass_per_kg;
  const double k = stiffness_Npm * inverse_mass_per_kg;
  const double discriminant = b * b - 4.0 * k;
  return discriminant > 0.0 ? 0.5 * (b + std::sqrt(discriminant)) : std::sqrt(k);
}
}  // namespace

double Plant::contact_rate_per_s(int pair, const PairGeometry& g, const Vec3& pole_axis,
                                 bool worst_case) const {
  const PoleConfig& pc = config_.pole;
  const double inertia = pole_transverse_inertia_kgm2();
  // A pole end at s n pushed along d: 1/m_eff = 1/m + |s n x d|^2 / I (the axial inertia plays
  // no part: the lever is along the axis). Across the pole this is largest (m_eff about m/4).
  const double lever_m = pc.longest_lever_m();  // the same bound for both ends
  const double across_inverse = 1.0 / pc.mass_kg + lever_m * lever_m / inertia;
  double normal_inverse = across_inverse;
  double tangential_inverse = across_inverse;
  const Surface surface = pair_surface(pair);
  if (!worst_case) {
    normal_inverse = 1.0 / pc.mass_kg + (lever_m * pole_axis).cross(g.normal).squaredNorm() / inertia;
    if (surface != Surface::floor) {  // the plate's vehicle moves too
      const int v = surface == Surface::plate1 ? 0 : 1;
      const Vec3& I = vehicle_inertia_kgm2_[v];
      const double vehicle_inertia = std::min({I.x(), I.y(), I.z()});
      const double mass_kg = vehicle_mass_kg_[v];
      normal_inverse += 1.0 / mass_kg + g.lever_vehicle_m.cross(g.normal).squaredNorm() / vehicle_inertia;
      tangential_inverse += 1.0 / mass_kg + g.lever_vehicle_m.squaredNorm() / vehicle_inertia;
    }
  }
  const ContactLaw& l = law(surface);
  // The sinking-in damper's slope is at most c (tanh); the rebound damper is linear.
  const double damping = std::max(l.damping_Nspm, l.rebound_damping_Nspm);
  return std::max(
      fastest_root_per_s(l.stiffness_Npm, damping, normal_inverse),
      fastest_root_per_s(l.tangential_stiffness_Npm, l.tangential_damping_Nspm, tangential_inverse));
}

std::int64_t Plant::choose_step_ns(std::int64_t limit_ns, const Bodies& b, const Kinematics& k) const {
  const double free_s = static_cast<double>(free_step_ns_) * 1e-9;
  // Only the pole's ends need the short step: the plate's damper and the floor on the small
  // effective mass of a rod's end are stiff at 1 ms, while a vehicle on its feet (four times a
  // quarter of its mass) is not.
  const bool by_mass = config_.integration.contact_step_by_mass != 0;
  const double contact_s = static_cast<double>(contact_step_ns_) * 1e-9;
  bool near = false;
  double step_s = free_s;
  auto shorten = [&](int p, const PairGeometry& g) {
    near = true;
    if (!by_mass) return;
    const double worst =
        pair_surface(p) == Surface::floor ? worst_rate_floor_per_s_ : worst_rate_plate_per_s_;
    const double rate = contact_rate_per_s(p, g, k.pole_rotation.col(2), false);
    step_s = std::min(step_s, std::max(contact_s, contact_s * worst / rate));
  };
  for (int p = 0; p < kPolePairs && !(near && !by_mass) && !pole_asleep_; ++p) {
    if (pairs_[p].engaged) {
      shorten(p, geometry(b, k, p));
      continue;
    }
    if (gap_m(k, p) < -kPlacementTolerance_m) continue;  // inside without contact: cannot engage
    const PairGeometry g = geometry(b, k, p);
    const double closing_mps = std::max(0.0, -g.relative_velocity_mps.dot(g.normal));
    if (g.gap_m > kNearMargin_m + 2.0 * free_s * closing_mps) continue;
    if (pair_surface(p) != Surface::floor) {
      const Vec3 d = g.point_m - k.plate_centre[pair_surface(p) == Surface::plate1 ? 0 : 1];
      const double radial_m = (d - d.dot(g.normal) * g.normal).norm();
      const double sliding_mps =
          (g.relative_velocity_mps - g.relative_velocity_mps.dot(g.normal) * g.normal).norm();
      if (radial_m > config_.vehicle.plate_radius_m + kNearMargin_m + 2.0 * free_s * sliding_mps) continue;
    }
    // Arriving: the reference step, so that the impact begins where it does with it.
    near = true;
    step_s = std::min(step_s, contact_s);
  }
  if (!near) return std::min(limit_ns, free_step_ns_);
  if (!by_mass) return std::min(limit_ns, contact_step_ns_);
  // Equal steps up to the next sample, none longer than step_s.
  const std::int64_t h_ns = std::clamp<std::int64_t>(to_ns(step_s), contact_step_ns_, free_step_ns_);
  const std::int64_t count = (limit_ns + h_ns - 1) / h_ns;
  return (limit_ns + count - 1) / count;
}

void Plant::substep(std::int64_t h_ns, const Bodies& b0, const Kinematics& k0) {
  const double h = static_cast<double>(h_ns) * 1e-9;
  candidate_count_ = 0;
  for (int p = 0; p < kPairs; ++p) {
    PairMemory& m = pairs_[p];
    m.above_at_start = gap_m(k0, p) >= -kPlacementTolerance_m;
    if (m.engaged || m.above_at_start) candidates_[candidate_count_++] = static_cast<std::uint8_t>(p);
  }
  // The motors' lags in closed form: the thrusts at the step's start, middle and end (the
  // decays computed once where both vehicles' motors are alike).
  std::array<double, 2> decay_middle{}, decay_end{};
  for (std::size_t v = 0; v < 2; ++v) {
    const double tau_s = motor_time_constant_s_[v];
    if (v == 1 && tau_s == motor_time_constant_s_[0]) {
      decay_middle[1] = decay_middle[0];
      decay_end[1] = decay_end[0];
      continue;
    }
    decay_middle[v] = tau_s > 0.0 ? std::exp(-(0.5 * h) / tau_s) : 0.0;
    decay_end[v] = tau_s > 0.0 ? std::exp(-h / tau_s) : 0.0;
  }
  std::array<std::array<double, 4>, 2> thrust_end_N;
  RotorWrenches rotors_start, rotors_middle, rotors_end;
  for (std::size_t v = 0; v < 2; ++v) {
    rotors_start[v] = rotor_wrench(config_.vehicle, thrust_at(v, 1.0));
    rotors_middle[v] = rotor_wrench(config_.vehicle, thrust_at(v, decay_middle[v]));
    thrust_end_N[v] = thrust_at(v, decay_end[v]);
    rotors_end[v] = rotor_wrench(config_.vehicle, thrust_end_N[v]);
  }

  // Classic RK4; the contact memory (engagement, anchors) is held over the step.
  const Evaluation e1 = evaluate(b0, k0, rotors_start);
  const Bodies b2 = advance(b0, e1, 0.5 * h);
  const Evaluation e2 = evaluate(b2, kinematics(b2), rotors_middle);
  const Bodies b3 = advance(b0, e2, 0.5 * h);
  const Evaluation e3 = evaluate(b3, kinematics(b3), rotors_middle);
  const Bodies b4 = advance(b0, e3, h);
  const Evaluation e4 = evaluate(b4, kinematics(b4), rotors_end);

  Evaluation mean;
  auto average = [](const auto& x1, const auto& x2, const auto& x3, const auto& x4) {
    return (x1 + 2.0 * x2 + 2.0 * x3 + x4) * (1.0 / 6.0);
  };
  for (int v = 0; v < 2; ++v) {
    BodyRate& r = mean.vehicle[v];
    r.dp = average(e1.vehicle[v].dp, e2.vehicle[v].dp, e3.vehicle[v].dp, e4.vehicle[v].dp);
    r.dv = average(e1.vehicle[v].dv, e2.vehicle[v].dv, e3.vehicle[v].dv, e4.vehicle[v].dv);
    r.dq = average(e1.vehicle[v].dq, e2.vehicle[v].dq, e3.vehicle[v].dq, e4.vehicle[v].dq);
    r.dw = average(e1.vehicle[v].dw, e2.vehicle[v].dw, e3.vehicle[v].dw, e4.vehicle[v].dw);
    // What the IMU integrates over the step, with the same quadrature weights.
    true_specific_force_[v] = average(e1.specific_force_body[v], e2.specific_force_body[v],
                                      e3.specific_force_body[v], e4.specific_force_body[v]);
    const Vec3 mean_rate = average(b0.vehicle[v].rate_body_radps, b2.vehicle[v].rate_body_radps,
                                   b3.vehicle[v].rate_body_radps, b4.vehicle[v].rate_body_radps);
    imu_sum_force_[v] += h * true_specific_force_[v];
    imu_sum_rate_[v] += h * mean_rate;
  }
  mean.pole.dp = average(e1.pole.dp, e2.pole.dp, e3.pole.dp, e4.pole.dp);
  mean.pole.dv = average(e1.pole.dv, e2.pole.dv, e3.pole.dv, e4.pole.dv);
  mean.pole.dq = average(e1.pole.dq, e2.pole.dq, e3.pole.dq, e4.pole.dq);
  mean.pole.dw = average(e1.pole.dw, e2.pole.dw, e3.pole.dw, e4.pole.dw);
  for (PairMemory& m : pairs_) m.force_N.setZero();
  for (int i = 0; i < candidate_count_; ++i) {
    const int p = candidates_[i];
    pairs_[p].force_N = average(e1.pair_force[p], e2.pair_force[p], e3.pair_force[p], e4.pair_force[p]);
  }
  imu_sum_time_s_ += h;

  store(advance(b0, mean, h));
  for (int v = 0; v < 2; ++v) vehicles_[v].motor_thrust_N = thrust_end_N[v];
  t_ns_ += h_ns;
  update_contacts();
  update_pole_rest(h);
}

void Plant::update_contacts() {
  const Bodies b = bodies();
  const Kinematics& k = kinematics_ = kinematics(b);
  kinematics_valid_ = true;
  for (int p = 0; p < kPairs; ++p) {
    PairMemory& m = pairs_[p];
    const bool was = m.engaged;
    const Surface surface = pair_surface(p);
    bool engaged = false;
    if ((m.engaged || m.above_at_start) && gap_m(k, p) < 0.0) {
      const PairGeometry g = geometry(b, k, p);
      engaged = g.within_rim;
      if (engaged) {
        const RigidBodyState* plate_body =
            surface == Surface::floor ? nullptr : &b.vehicle[surface == Surface::plate1 ? 0 : 1];
        const Vec3 on_surface = g.point_m - g.gap_m * g.normal;  // the point projected onto the surface
        Vec3 anchor_world = on_surface;
        if (m.anchored) {
          const Vec3 old_anchor =
              plate_body ? Vec3(plate_body->position_m + plate_body->attitude * m.anchor) : m.anchor;
          const Vec3 offset = on_surface - old_anchor;
          const Vec3 tangential = offset - offset.dot(g.normal) * g.normal;
          const ContactLaw& l = law(surface);
          const double f_n = contact_normal_force_N(l, -g.gap_m, g.relative_velocity_mps.dot(g.normal));
          anchor_world = on_surface - slipped_anchor_offset_m(l, f_n, tangential);
        }
        m.anchor = plate_body
                       ? Vec3(plate_body->attitude.conjugate() * (anchor_world - plate_body->position_m))
                       : anchor_world;
      }
    }
    m.engaged = engaged;
    m.anchored = engaged;
    if (p < kPolePairs && was != m.engaged)
      events_.push_back(PoleContactEvent{t_s(), p / 3, surface, m.engaged});
  }
}

void Plant::update_pole_rest(double h_s) {
  if (pole_asleep_) return;
  // Both ends on the floor (pairs 2 and 5) and (nearly) still. The spin about the pole's own axis
  // does not count: the ends are points on the axis, so nothing in the plant damps it, and it
  // moves nothing.
  const Vec3 tumble_radps = pole_.body.rate_body_radps - pole_.body.rate_body_radps.z() * Vec3::UnitZ();
  const bool resting = pairs_[2].engaged && pairs_[5].engaged &&
                       pole_.body.velocity_mps.norm() < kRestSpeed_mps &&
                       tumble_radps.norm() < kRestRate_radps;
  pole_rest_s_ = resting ? pole_rest_s_ + h_s : 0.0;
  if (pole_rest_s_ >= kRestTime_s) {
    kinematics_valid_ = false;
    pole_asleep_ = true;
    pole_.body.velocity_mps.setZero();
    pole_.body.rate_body_radps.setZero();
  }
}

void Plant::step(double dt_s, const MotorCommands& vehicle1, const MotorCommands& vehicle2) {
  if (!(std::isfinite(dt_s) && dt_s > 0.0)) return;
  const std::int64_t end_ns = t_ns_ + to_ns(dt_s);
  const std::array<const MotorCommands*, 2> commands{&vehicle1, &vehicle2};
  for (int v = 0; v < 2; ++v) {
    for (int i = 0; i < 4; ++i) {
      target_thrust_N_[v][i] = motor_target_thrust_N(commands[v]->command[i], motor_gain_[v][i],
                                                     config_.vehicle.motor_thrust_max_N);
    }
  }
  const bool battery = config_.battery.enabled != 0;
  if (battery) {
    // The voltage under the thrust the motors make as the step begins, held over it like the
    // commands (the current follows the motors' lag, tens of milliseconds).
    load_batteries();
    for (int v = 0; v < 2; ++v) {
      const double factor = thrust_voltage_factor(battery_[v].voltage_V, config_.battery.reference_voltage_V);
      for (double& f : target_thrust_N_[v]) f *= factor;
    }
  }
  const std::int64_t start_ns = t_ns_;
  if (t_ns_ >= static_cast<std::int64_t>(mocap_index_) * mocap_period_ns_) capture_mocap();
  while (t_ns_ < end_ns) {
    const std::int64_t next_imu_ns = static_cast<std::int64_t>(imu_tick_ + 1) * imu_period_ns_;
    const std::int64_t next_mocap_ns = static_cast<std::int64_t>(mocap_index_) * mocap_period_ns_;
    const std::int64_t limit_ns = std::min({end_ns, next_imu_ns, next_mocap_ns}) - t_ns_;
    const Bodies b = bodies();
    if (!kinematics_valid_) kinematics_ = kinematics(b);
    // (update_contacts() leaves the kinematics of the state it ends in for the next substep.)
    const Kinematics k = kinematics_;
    substep(choose_step_ns(limit_ns, b, k), b, k);
    if (t_ns_ == next_imu_ns) sample_imu();
    if (t_ns_ == next_mocap_ns) capture_mocap();
  }
  if (battery) {
    const double hours = static_cast<double>(t_ns_ - start_ns) * 1e-9 / 3600.0;
    for (BatteryState& b : battery_) b.charge_drawn_Ah += b.current_A * hours;
  }
}

void Plant::swap_battery(pa::VehicleId vehicle) {
  const std::size_t v = slot(vehicle);
  charge_start_[v] = 1.0;
  battery_[v] = BatteryState{};
  battery_[v].voltage_V = battery_open_circuit_V(config_.battery, 1.0);
}

void Plant::load_batteries() {
  const BatteryConfig& bc = config_.battery;
  for (int v = 0; v < 2; ++v) {
    BatteryState& b = battery_[v];
    double power_W = 0.0;
    for (const double f : vehicles_[v].motor_thrust_N)
      power_W += motor_electrical_power_W(f, config_.vehicle, config_.air_density_kgpm3);
    b.state_of_charge = std::max(0.0, charge_start_[v] - b.charge_drawn_Ah / bc.capacity_Ah);
    b.voltage_V = battery_terminal_V(battery_open_circuit_V(bc, b.state_of_charge), power_W,
                                     bc.internal_resistance_ohm);
    b.current_A = power_W / b.voltage_V;
  }
}

void Plant::sample_imu() {
  ++imu_tick_;
  for (int v = 0; v < 2; ++v) {
    const Vec3 force = imu_sum_force_[v] / imu_sum_time_s_;
    const Vec3 rate = imu_sum_rate_[v] / imu_sum_time_s_;
    latest_imu_[v] = imu_[v].measure(imu_tick_, t_s(), rate, force);
    imu_queue_[v].push_back(latest_imu_[v]);
    if (imu_queue_[v].size() > kImuQueueLimit) imu_queue_[v].pop_front();
    imu_sum_force_[v] = Vec3::Zero();
    imu_sum_rate_[v] = Vec3::Zero();
  }
  imu_sum_time_s_ = 0.0;
}

void Plant::capture_mocap() {
  // The pole's markers give its middle, which the ground station takes as the centre of mass.
  RigidBodyState pole_markers = pole_.body;
  pole_markers.position_m = pole_.point_m(-config_.pole.centre_of_mass_offset_m);
  mocap_.capture(mocap_index_, t_s(), {vehicles_[0].body, vehicles_[1].body, pole_markers}, losses_active());
  ++mocap_index_;
}

bool Plant::losses_active() const {
  return config_.losses_only_in_pole_flight == 0 || pole_contact() == Contact::none;
}

bool Plant::pop_imu(pa::VehicleId vehicle, ImuSample& out) {
  auto& q = imu_queue_[slot(vehicle)];
  if (q.empty()) return false;
  out = q.front();
  q.pop_front();
  return true;
}

// --- contacts, reported ------------------------------------------------------------------------

Contact Plant::pole_end_contact(int end) const {
  const int base = (end == 0 ? 0 : 1) * 3;
  for (int s = 0; s < 3; ++s) {
    if (pairs_[base + s].engaged) return contact_of(static_cast<Surface>(s));
  }
  return Contact::none;
}

Contact Plant::pole_contact() const {
  const Contact a = pole_end_contact(0);
  const Contact b = pole_end_contact(1);
  for (const Contact c : {Contact::vehicle1, Contact::vehicle2, Contact::floor}) {
    if (a == c || b == c) return c;
  }
  return Contact::none;
}

Vec3 Plant::pole_end_force_N(int end, Surface surface) const {
  return pairs_[(end == 0 ? 0 : 3) + static_cast<int>(surface)].force_N;
}

bool Plant::vehicle_on_floor(pa::VehicleId vehicle) const {
  const int base = kPolePairs + 4 * static_cast<int>(slot(vehicle));
  for (int f = 0; f < 4; ++f) {
    if (pairs_[base + f].engaged) return true;
  }
  return false;
}

std::vector<PoleContactEvent> Plant::take_contact_events() {
  std::vector<PoleContactEvent> out;
  out.swap(events_);
  return out;
}

// --- diagnostics ------------------------------------------------------------------------------

double Plant::pole_transverse_inertia_kgm2() const {
  const PoleConfig& p = config_.pole;
  // A thin-walled tube of length 2L and radius r about a transverse axis through its middle,
  // moved to the centre of mass d off it (parallel axes: I_cm = I_middle - m d^2).
  const double d = p.centre_of_mass_offset_m;
  return p.mass_kg * (p.half_length_m * p.half_length_m / 3.0 + p.radius_m * p.radius_m / 2.0 - d * d);
}

double Plant::pole_axial_inertia_kgm2() const {
  return config_.pole.mass_kg * config_.pole.radius_m * config_.pole.radius_m;
}

double Plant::pole_energy_J() const {
  const RigidBodyState& b = pole_.body;
  const Vec3 inertia(pole_transverse_inertia_kgm2(), pole_transverse_inertia_kgm2(),
                     pole_axial_inertia_kgm2());
  const double m = config_.pole.mass_kg;
  return 0.5 * m * b.velocity_mps.squaredNorm() +
         0.5 * b.rate_body_radps.dot(inertia.cwiseProduct(b.rate_body_radps)) +
         m * config_.gravity_mps2 * b.position_m.z();
}

double Plant::vehicle_energy_J(pa::VehicleId vehicle) const {
  const std::size_t v = slot(vehicle);
  const RigidBodyState& b = vehicles_[v].body;
  const Vec3& inertia = vehicle_inertia_kgm2_[v];
  const double mass_kg = vehicle_mass_kg_[v];
  return 0.5 * mass_kg * b.velocity_mps.squaredNorm() +
         0.5 * b.rate_body_radps.dot(inertia.cwiseProduct(b.rate_body_radps)) +
         mass_kg * config_.gravity_mps2 * b.position_m.z();
}

Vec3 Plant::pole_momentum_Ns() const { return config_.pole.mass_kg * pole_.body.velocity_mps; }

Vec3 Plant::vehicle_momentum_Ns(pa::VehicleId vehicle) const {
  return vehicle_mass_kg_[slot(vehicle)] * vehicles_[slot(vehicle)].body.velocity_mps;
}

Vec3 Plant::pole_angular_momentum_Nms(const Vec3& about_m) const {
  const RigidBodyState& b = pole_.body;
  const Vec3 inertia(pole_transverse_inertia_kgm2(), pole_transverse_inertia_kgm2(),
                     pole_axial_inertia_kgm2());
  return (b.position_m - about_m).cross(pole_momentum_Ns()) +
         b.attitude * inertia.cwiseProduct(b.rate_body_radps);
}

Vec3 Plant::vehicle_angular_momentum_Nms(pa::VehicleId vehicle, const Vec3& about_m) const {
  const RigidBodyState& b = vehicles_[slot(vehicle)].body;
  const Vec3& inertia = vehicle_inertia_kgm2_[slot(vehicle)];
  return (b.position_m - about_m).cross(vehicle_momentum_Ns(vehicle)) +
         b.attitude * inertia.cwiseProduct(b.rate_body_radps);
}

}  // namespace hil
