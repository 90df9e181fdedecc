// One vehicle as the ground station measures it in flight and adapts to it, apart from the
// mission: its thrust gain (a setpoint carries a_q / k, thrust_compensation.hpp), each take-off's
// identification flight and the motor lag and inertia set on board from its fit
// (motor_equaliser.hpp, adaptation/identification_memory.hpp), the noise on its motion-capture
// poses and from it the trust its pole filter gives them (estimation::PoleTrust), and its
// gyro-held attitude set back onto motion capture's (estimation/onboard_tilt.hpp).
// It sends nothing itself: a step returns the commands to send, and the runtime hands back each
// one's handle (vehicle_adaptation_test.cpp).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Geometry>

#include "groundstation/adaptation/identification_memory.hpp"
#include "groundstation/estimation/mocap_noise.hpp"
#include "groundstation/estimation/onboard_tilt.hpp"
#include "groundstation/estimation/pole_on_vehicle_ekf.hpp"
#include "groundstation/estimation/rate_response.hpp"
#include "groundstation/estimation/thrust_gain.hpp"
#include "groundstation/link/ground_link.hpp"
#include "groundstation/mission/vehicle_sequencer.hpp"
#include "groundstation/model/vehicle.hpp"
#include "groundstation/model/vehicle_limits.hpp"
#include "groundstation/runtime/motor_equaliser.hpp"

namespace gs::runtime {

// GroundStationConfig's fields of the same names (ground_station_config.hpp says why each).
struct VehicleAdaptationSettings {
  estimation::ThrustGainConfig thrust_gain;
  bool compensate_thrust_gain = true;
  double thrust_gain_min_height_m = 0.3;
  double pole_weight_mps2 = 0.0;  // TaskSettings::pole_weight_mps2: the balanced pole's load
  estimation::RateLoopConfig rate_loop;
  estimation::RateResponseSettings rate_response;
  estimation::PoleTrust pole_trust;
  model::VehicleLimits limits;
  double airframe_thrust_max_mps2 = 0.0;
};

// A COMMAND for the vehicle: SET_MOTOR_TIME_CONSTANT or SET_INERTIA_SCALE with the value it sets,
// or CORRECT_TILT.
struct OnBoardCommand {
  pa::proto::CommandCode code = pa::proto::CommandCode::correct_tilt;
  std::int32_t argument = 0;
  double value = 0.0;
};

class VehicleAdaptation {
 public:
  VehicleAdaptation(pa::VehicleId vehicle, const VehicleAdaptationSettings& settings);

  // A motion-capture pose of the vehicle flying `task`, captured at `t_s` and arrived at `now_s`:
  // its noise (measured while it holds still or hovers) and its thrust gain. Every
  // PoleTrust::judge_period_s, the sigma its pole filter is to give its poses.
  std::optional<double> on_pose(double t_s, double now_s, const estimation::MocapPose& pose,
                                mission::Task task);

  // The lag and inertia kept from the vehicle's last accepted identification (possibly an
  // earlier run's), to set as it arms, before this flight's own.
  std::vector<OnBoardCommand> at_arming(const adaptation::IdentificationMemory& memory) const;
  // The identification flight over a tick of `task` (`at_target`: the task's target reached): the
  // retry of a refused flight started only while the vehicle holds its target without the pole,
  // and a finished flight's fit recorded; a lag that differs from the equaliser's by more than the
  // fit's accuracy goes on board, and so does a lighter inertia for the rate loop. A refused fit
  // keeps what is set.
  std::vector<OnBoardCommand> identify(double now_s, mission::Task task, bool at_target,
                                       adaptation::IdentificationMemory& memory);
  // The lag's and inertia's commands in flight come to what `state_of(handle)` says.
  template <class StateOf>
  void settle(StateOf state_of) {
    for (OnBoardSetting* s : {&motors_.lag(), &motors_.inertia()})
      if (s->pending()) s->settle(state_of(*s->pending()));
  }
  // `command` went out as `handle`.
  void sent(const OnBoardCommand& command, const link::CommandHandle& handle);

  // The vehicle's attitude report while the ground station flies it on motion capture (rotating
  // at `rate_radps`): CORRECT_TILT once its up has drifted from motion capture's.
  std::optional<OnBoardCommand> tilt_correction(double now_s, const Eigen::Quaterniond& onboard,
                                                const Eigen::Quaterniond& measured, double rate_radps);

  // The setpoint for the law's `u`: its thrust over the gain (thrust_compensation.hpp), the
  // identification's excitation on the roll and pitch rates.
  model::VehicleInput setpoint(model::VehicleInput u, double now_s) const;
  // The link sent `sent` at `now_s`, to act at `t_acts_s`: the identification and the thrust-gain
  // estimator are told what was commanded; returned, what the vehicle delivers (k a_q), for the
  // estimator's model.
  model::VehicleInput delivered(model::VehicleInput sent, double now_s, double t_acts_s);

  // The vehicle reports its pack's voltage, so it compensates for the pack on board.
  void set_voltage_compensated(bool compensated) { thrust_gain_.set_voltage_compensated(compensated); }
  void start_identification(double now_s) { motors_.start_identification(now_s); }
  IdentificationFlight& identification_flight() { return motors_.flight(); }

  const estimation::ThrustGainEstimator& thrust_gain() const { return thrust_gain_; }
  const MotorEqualiser& motors() const { return motors_; }

 private:
  double gain() const { return settings_.compensate_thrust_gain ? thrust_gain_.gain() : 1.0; }
  OnBoardCommand motor_lag(double lag_s) const;
  OnBoardCommand inertia_scale(double scale) const;

  pa::VehicleId vehicle_;
  VehicleAdaptationSettings settings_;
  estimation::ThrustGainEstimator thrust_gain_;
  MotorEqualiser motors_;
  estimation::MocapNoiseMeter noise_;
  estimation::OnboardTilt onboard_tilt_;
  double pole_trust_s_ = -1e9;  // when its pole filter's trust was last judged
};

}  // namespace gs::runtime
