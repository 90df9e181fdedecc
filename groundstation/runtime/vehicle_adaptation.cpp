#include "groundstation/runtime/vehicle_adaptation.hpp"

#include <algorithm>
#include <limits>

#include "groundstation/runtime/thrust_compensation.hpp"

namespace gs::runtime {

VehicleAdaptation::VehicleAdaptation(pa::VehicleId vehicle, const VehicleAdaptationSettings& settings)
    : vehicle_(vehicle),
      settings_(settings),
      thrust_gain_(settings.thrust_gain),
      motors_(IdentificationFlight(
                  estimation::RateResponseIdentifier(settings.rate_loop, settings.rate_response)),
              settings.rate_loop.design_time_constant_s) {}

std::optional<double> VehicleAdaptation::on_pose(double t_s, double now_s, const estimation::MocapPose& pose,
                                                 mission::Task task) {
  using mission::Task;
  noise_.add(t_s, pose,
             task == Task::parked || task == Task::hover || task == Task::balance || task == Task::wait);
  std::optional<double> sigma;
  if (now_s - pole_trust_s_ >= settings_.pole_trust.judge_period_s) {
    pole_trust_s_ = now_s;
    const std::optional<estimation::MocapNoise> noise = noise_.noise();
    sigma = estimation::pole_measurement_sigma(
        motors_.equalised_s(),
        noise ? std::max(noise->position_sigma_m, noise->attitude_sigma_rad)
              : std::numeric_limits<double>::quiet_NaN(),
        settings_.pole_trust);
  }
  measure_thrust_gain(thrust_gain_, task, now_s, pose, settings_.thrust_gain_min_height_m,
                      settings_.pole_weight_mps2);
  return sigma;
}

OnBoardCommand VehicleAdaptation::motor_lag(double lag_s) const {
  return {pa::proto::CommandCode::set_motor_time_constant, motor_lag_argument_us(lag_s), lag_s};
}
OnBoardCommand VehicleAdaptation::inertia_scale(double scale) const {
  return {pa::proto::CommandCode::set_inertia_scale, inertia_scale_argument(scale), scale};
}

std::vector<OnBoardCommand> VehicleAdaptation::at_arming(
    const adaptation::IdentificationMemory& memory) const {
  std::vector<OnBoardCommand> commands;
  if (const std::optional<double> lag_s = memory.lag_at_arming(vehicle_))
    commands.push_back(motor_lag(*lag_s));
  if (const std::optional<double> scale = memory.inertia_scale_to_set(vehicle_, 1.0))
    commands.push_back(inertia_scale(*scale));
  return commands;
}

std::vector<OnBoardCommand> VehicleAdaptation::identify(double now_s, mission::Task task, bool at_target,
                                                        adaptation::IdentificationMemory& memory) {
  using mission::Task;
  // In hover at once (the pole comes within seconds), or at its waiting point for a catch once it
  // is there (a catcher goes to wait straight from its take-off; climbing there, the flight was
  // fitted 16 % slow). The catch manoeuvre, seconds later, stops a flight not yet over.
  // A retry is flown still, at the target (a thrower climbs to the throw's origin in hover).
  if (task != Task::hover && task != Task::wait && task != Task::take_off) motors_.cancel_retry();
  if (motors_.retry_due() && (task == Task::hover || task == Task::wait) && at_target)
    motors_.start_retry(now_s);
  std::vector<OnBoardCommand> commands;
  const std::optional<estimation::IdentificationResult> result = motors_.finish(now_s);
  if (!result) return commands;
  const std::optional<double> k =
      thrust_gain_.measurements() > 0 ? std::optional(thrust_gain_.gain()) : std::nullopt;
  if (const std::optional<double> lag_s = memory.finished(vehicle_, *result, k, now_s, motors_.equalised_s()))
    commands.push_back(motor_lag(*lag_s));
  if (!result->identified) return commands;
  if (const std::optional<double> scale = memory.inertia_scale_to_set(vehicle_, motors_.inertia_scale()))
    commands.push_back(inertia_scale(*scale));
  return commands;
}

void VehicleAdaptation::sent(const OnBoardCommand& command, const link::CommandHandle& handle) {
  if (command.code == pa::proto::CommandCode::set_motor_time_constant)
    motors_.lag().sent(command.value, handle);
  if (command.code == pa::proto::CommandCode::set_inertia_scale)
    motors_.inertia().sent(command.value, handle);
}

std::optional<OnBoardCommand> VehicleAdaptation::tilt_correction(double now_s,
                                                                 const Eigen::Quaterniond& onboard,
                                                                 const Eigen::Quaterniond& measured,
                                                                 double rate_radps) {
  const std::optional<Eigen::Vector2d> up = onboard_tilt_.report(now_s, onboard, measured, rate_radps);
  if (!up) return std::nullopt;
  return OnBoardCommand{pa::proto::CommandCode::correct_tilt, estimation::tilt_correction_argument(*up), 0.0};
}

// The setpoint carries a_q / k (the vehicle delivers k a_q); the estimator's model is told what
// the vehicle delivers, the thrust-gain estimator what it was commanded.
model::VehicleInput VehicleAdaptation::setpoint(model::VehicleInput u, double now_s) const {
  u.a_q_mps2 =
      compensated_thrust_mps2(u.a_q_mps2, gain(), settings_.limits, settings_.airframe_thrust_max_mps2);
  u.omega_radps.head<2>() += motors_.flight().excitation(now_s);
  return u;
}

model::VehicleInput VehicleAdaptation::delivered(model::VehicleInput sent, double now_s, double t_acts_s) {
  const double k = gain();  // the one the setpoint was divided by
  motors_.flight().command_sent(now_s, sent.omega_radps.head<2>());
  thrust_gain_.command(t_acts_s, sent.a_q_mps2);
  sent.a_q_mps2 *= k;
  return sent;
}

}  // namespace gs::runtime
