#include "groundstation/dds/telemetry_conversion.hpp"

#include <Eigen/Geometry>

#include "groundstation/dds/mocap_conversion.hpp"

namespace gs::dds {
namespace {

// The messages' constants are the ground station's and the protocol's enums, value for value, so
// that a ROS 2 tool reads the task and the vehicle's mode by the .msg file's names.
using mission::Task;
template <class Enum>
constexpr bool same(int constant, Enum value) {
  return constant == static_cast<int>(value);
}
static_assert(same(pa_msgs_msg_VehicleTelemetry_Constants_TASK_PARKED, Task::parked));
static_assert(same(pa_msgs_msg_VehicleTelemetry_Constants_TASK_ARMING, Task::arming));
static_assert(same(pa_msgs_msg_VehicleTelemetry_Constants_TASK_TAKE_OFF, Task::take_off));
static_assert(same(pa_msgs_msg_VehicleTelemetry_Constants_TASK_HOVER, Task::hover));
static_assert(same(pa_msgs_msg_VehicleTelemetry_Constants_TASK_BALANCE, Task::balance));
static_assert(same(pa_msgs_msg_VehicleTelemetry_Constants_TASK_THROWING, Task::throwing));
static_assert(same(pa_msgs_msg_VehicleTelemetry_Constants_TASK_RELEASE, Task::release));
static_assert(same(pa_msgs_msg_VehicleTelemetry_Constants_TASK_RETREAT, Task::retreat));
static_assert(same(pa_msgs_msg_VehicleTelemetry_Constants_TASK_WAIT, Task::wait));
static_assert(same(pa_msgs_msg_VehicleTelemetry_Constants_TASK_CATCHING, Task::catching));
static_assert(same(pa_msgs_msg_VehicleTelemetry_Constants_TASK_REBALANCE, Task::rebalance));
static_assert(same(pa_msgs_msg_VehicleTelemetry_Constants_TASK_CLEAR, Task::clear));
static_assert(same(pa_msgs_msg_VehicleTelemetry_Constants_TASK_LANDING, Task::landing));
static_assert(same(pa_msgs_msg_VehicleTelemetry_Constants_TASK_FAILSAFE, Task::failsafe));
static_assert(same(pa_msgs_msg_VehicleTelemetry_Constants_TASK_DESCEND, Task::descend));
static_assert(mission::kTaskCount == 15, "a task added: add it to VehicleTelemetry.msg and here");
using pa::proto::Mode;
static_assert(same(pa_msgs_msg_VehicleTelemetry_Constants_MODE_DISARMED, Mode::disarmed));
static_assert(same(pa_msgs_msg_VehicleTelemetry_Constants_MODE_ARMED, Mode::armed));
static_assert(same(pa_msgs_msg_VehicleTelemetry_Constants_MODE_FLYING, Mode::flying));
static_assert(same(pa_msgs_msg_VehicleTelemetry_Constants_MODE_FAILSAFE_HOVER, Mode::failsafe_hover));
static_assert(same(pa_msgs_msg_VehicleTelemetry_Constants_MODE_FAILSAFE_DESCENT, Mode::failsafe_descent));
static_assert(same(pa_msgs_msg_VehicleTelemetry_Constants_MODE_LANDED, Mode::landed));
static_assert(same(pa_msgs_msg_VehicleTelemetry_Constants_MODE_KILLED, Mode::killed));
static_assert(same(pa_msgs_msg_VehicleTelemetry_Constants_MODE_HOLD, Mode::hold));
static_assert(pa::proto::kModeMax == 7, "a mode added: add it to VehicleTelemetry.msg and here");

geometry_msgs_msg_dds__Point_ point(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }
geometry_msgs_msg_dds__Vector3_ vector3(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }
template <class Message>
Eigen::Vector3d eigen(const Message& v) {
  return {v.x, v.y, v.z};
}

}  // namespace

Eigen::Quaterniond vehicle_attitude(const model::VehicleState& s) {
  // ^I_B R = Rz(psi) Ry(theta) Rx(phi) (estimation/mocap_pose.hpp).
  return Eigen::AngleAxisd(s.psi_rad, Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(s.theta_rad, Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(s.phi_rad, Eigen::Vector3d::UnitX());
}

std::string vehicle_telemetry_topic(pa::VehicleId vehicle) {
  if (!pa::is_act_vehicle(vehicle)) return {};
  return "rt/pa/vehicle" + std::to_string(vehicle.node()) + "/telemetry";
}

std::uint8_t link_state_to_ros(const link::VehicleLinkStatus& status) {
  if (!status.heard) return link_state::kUnheard;
  return status.lost ? link_state::kLost : link_state::kUp;
}

VehicleTelemetry vehicle_telemetry_to_ros(pa::VehicleId vehicle, std::int64_t stamp_ns,
                                          const link::VehicleLinkStatus& status, mission::Task task,
                                          const std::optional<estimation::VehicleEstimate>& estimate) {
  VehicleTelemetry out{};
  out.stamp = ros_time(stamp_ns);
  out.vehicle = vehicle.node();
  out.link = link_state_to_ros(status);
  out.task = static_cast<std::uint8_t>(task);
  out.vehicle_mode = static_cast<std::uint8_t>(status.mode);
  out.estimate_valid = estimate.has_value();
  if (estimate) {
    const model::VehicleState& s = estimate->state;
    const Eigen::Quaterniond q = vehicle_attitude(s);
    out.position = point(s.p_m);
    out.velocity = vector3(s.v_mps);
    out.orientation = {q.x(), q.y(), q.z(), q.w()};  // ROS: (x, y, z, w)
    out.body_rate = vector3(estimate->body_rates_radps);
  }
  return out;
}

std::uint8_t pole_mode_to_ros(estimation::PoleMode mode) {
  switch (mode) {
    case estimation::PoleMode::on_vehicle1: return pole_mode::kOnVehicle1;
    case estimation::PoleMode::on_vehicle2: return pole_mode::kOnVehicle2;
    case estimation::PoleMode::free: break;
  }
  return pole_mode::kFree;
}

std::optional<estimation::PoleMode> pole_mode_from_ros(std::uint8_t mode) {
  switch (mode) {
    case pole_mode::kFree: return estimation::PoleMode::free;
    case pole_mode::kOnVehicle1: return estimation::PoleMode::on_vehicle1;
    case pole_mode::kOnVehicle2: return estimation::PoleMode::on_vehicle2;
    default: return std::nullopt;
  }
}

PoleTelemetry pole_telemetry_to_ros(const estimation::PoleEstimate& pole, std::int64_t stamp_ns,
                                    const std::optional<CatchForecast>& forecast) {
  PoleTelemetry out{};
  out.stamp = ros_time(stamp_ns);
  out.estimate_valid = pole.valid;
  out.mode = pole_mode_to_ros(pole.mode);
  out.position = point(pole.state.p_m);
  out.velocity = vector3(pole.state.v_mps);
  out.direction = vector3(pole.state.n);
  out.angular_velocity = vector3(pole.state.omega_radps);
  out.catch_predicted = forecast.has_value();
  if (forecast) {
    out.catch_stamp = ros_time(forecast->stamp_ns);
    out.catch_point = point(forecast->point_m);
    out.catch_vehicle = forecast->catcher.node();
  }
  return out;
}

model::PoleState pole_state_from_ros(const PoleTelemetry& t) {
  return {eigen(t.position), eigen(t.velocity), eigen(t.direction), eigen(t.angular_velocity)};
}

}  // namespace gs::dds
