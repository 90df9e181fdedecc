// The task controllers: for one vehicle at one motion-capture frame, the law its mission task
// flies (control/task_laws.hpp) on the estimate predicted to when the command acts, to a command
// within the vehicle's limits. Hover, waiting, take-off (with its ramp), retreat, clear and
// rebalance fly the hover LQR about the carrot; balance the balancing LQR about the pole's
// resting end; throwing the throw's TV-LQR (planning/throw_command.hpp) with the learnt shift;
// release its open-loop pitch-back; catching the hover LQR about the catch manoeuvre's reference.
// State is what the caller passes in (TaskState, the vehicle's carrot, integral and ramp); no
// clock, no link: the runtime sends what comes back (task_control_test.cpp).
#pragma once

#include <optional>

#include <Eigen/Core>

#include "groundstation/adaptation/throw_learning.hpp"
#include "groundstation/control/lqr.hpp"
#include "groundstation/control/task_laws.hpp"
#include "groundstation/control/throw_frame.hpp"
#include "groundstation/estimation/state_estimator.hpp"
#include "groundstation/mission/vehicle_sequencer.hpp"
#include "groundstation/model/vehicle_limits.hpp"
#include "groundstation/planning/catch_trajectory.hpp"
#include "groundstation/planning/height_shift.hpp"
#include "groundstation/planning/throw_tracking.hpp"
#include "groundstation/planning/throw_trajectory.hpp"

namespace gs::runtime {

struct TaskControlSettings {
  // Carrot speed and acceleration: set points move towards their target at most this fast, so
  // that the hover and balancing LQRs only ever see small position errors (they are linear
  // designs), and brake to stop on it.
  control::CarrotLimits carrot{1.0, 1.0};
  // Integral action in hover, balance and the catch (1/s): the LQR's reference position is the
  // set point plus this times the integral of (set point - position), so that a constant force
  // offset (the motors' spread, the pole's weight, drag) leaves no position error. Slow beside
  // the LQRs' position loops (about 1.5 rad/s), so it does not destabilise them. Each axis of
  // the integral is bounded to +-1 m s (0.3 m of reference shift); it integrates in take-off
  // only above 0.2 m, clear of the legs' ground contact, which holds the vehicle against it.
  double position_integral_gain = 0.3;
  double position_integral_limit_ms = 1.0;
  double take_off_integral_height_m = 0.2;
  // A vehicle still below that height this long into its take-off is weaker than its thrust gain
  // says (the gain is measured only in flight): its thrust ramps up at this rate until it leaves
  // the floor, as PX4's take-off ramp does. Measured: the vehicles of the airframe file pass 0.2 m
  // within 0.6 s; one drawn from the envelope with k 0.78 sat on the floor at the commanded g.
  // In the air the ramp falls back at the same rate.
  double take_off_ramp_after_s = 1.0;
  double take_off_ramp_mps3 = 3.0;
  double pole_weight_mps2 = 0.03 * 9.81 / 0.52;  // m_p g / m_q (hil/config/plant.yaml values)
  // The throw: balancing with the tilt below this first (GroundStationConfig::conditions).
  double balance_settled_rad = 0.03;
  // The laws flown about a set point (hover and its kin, balance) never tilt the vehicle beyond
  // 0.7 rad (40 degrees; control/task_laws.hpp); the catch manoeuvre tilts it up to ~23 degrees,
  // a balanced pole a few. Measured on the envelope: the hover law asked to stop a catcher that
  // a falling pole had led away at 5 m/s, with its set point 3.6 m behind, and pitched it over.
  control::TiltLimit tilt_limit;
  // The release after T (Section VII-A leaves it open): minimum thrust for conditions.release_low_s
  // with the plate pitching back at the launch rate for release_pitch_s, then level, roll and
  // pitch brought back at 8 /s (a time constant of 0.125 s, inside the firmware's rate loop).
  double release_pitch_s = 0.1;
  double release_level_gain_per_s = 8.0;
  // The launch state is taken from a throw command at most this long before T (commands come
  // with the motion capture, every 5 ms).
  double launch_state_window_s = 0.012;
};

// What one vehicle's laws carry from frame to frame.
struct TaskState {
  Eigen::Vector3d target_m = Eigen::Vector3d::Zero();  // where the task wants the CG
  control::SetPoint set_point;                         // the carrot moving towards it
  Eigen::Vector3d integral = Eigen::Vector3d::Zero();  // of the position error
  double take_off_ramp_mps2 = 0.0;                     // see take_off_ramp_mps3
};

// One vehicle at one frame, predicted to when its command acts (t_act_s).
struct TaskFrame {
  mission::Task task = mission::Task::hover;
  double now_s = 0.0;
  double t_act_s = 0.0;
  double dt_s = 0.0;          // since the last frame
  double task_since_s = 0.0;  // the sequencer's
  estimation::VehicleEstimate vehicle;
  estimation::PoleEstimate pole;
  estimation::PlateKinematics plate;
  double half_length_m = 0.0;
  Eigen::Vector3d waiting_target_m = Eigen::Vector3d::Zero();  // the wait task's target
  // How much longer than the design's its motors lag, as identified (0 for faster ones): the
  // throw's feed-forward leads by it (planning::throw_step).
  double motor_lead_s = 0.0;
};

// The attempt's throw as the throwing and release tasks fly it, and its catch.
struct FlownThrow {
  const planning::ThrowTrajectory* trajectory = nullptr;
  const planning::ThrowTracker* tracker = nullptr;
  control::ThrowFrame frame;
  // The pole's resting end from the plate's centre as the throw started, in the plate's axes.
  Eigen::Vector3d resting_offset_m = Eigen::Vector3d::Zero();
  // The learnt throw's correction (throw_learning.hpp); none for a throw to a target, which is
  // planned anew each time.
  const adaptation::ThrowCorrection* correction = nullptr;
  const planning::CatchTrajectory* catch_trajectory = nullptr;  // none yet: hover where it is
  double catch_start_s = 0.0;
  const planning::HeightShift* catch_height_shift = nullptr;  // added to its z (none: 0)
};

// The throw's tracked state near its end (tau within launch_state_window_s of T).
struct ThrowEnd {
  double tau_s = 0.0;
  model::PlanarState<double> state;
};

struct TaskCommand {
  std::optional<model::VehicleInput> input;
  // Balance: whether the pole stands within balance_settled_rad (the throw waits for it).
  std::optional<bool> pole_settled;
  std::optional<ThrowEnd> throw_end;  // throwing, near T
};

// The tasks that fly a law on the estimate; the others send a fixed command or none.
bool flies_law(mission::Task task);
// Parked and arming: zero thrust (ARM needs a zero-thrust setpoint, fw/supervisor.hpp); landing
// and failsafe: none (LAND flies on board; the firmware levels and descends when the stream stops).
std::optional<model::VehicleInput> fixed_command(mission::Task task);

// The pole's tilt from the vertical (either end up).
double tilt_rad(const model::PoleState& pole);

// Where the pole rests: its end at the plate (the on-vehicle filter estimates where on the plate
// it landed), moving with the plate.
control::Pivot resting_pivot(const estimation::PlateKinematics& plate, const model::PoleState& pole,
                             double half_length_m);

// The pole's resting end from the plate's centre in the plate's axes, which the throw keeps fixed
// on the plate as it started (FlownThrow::resting_offset_m).
Eigen::Vector3d resting_offset_m(const estimation::PlateKinematics& plate, const model::PoleState& pole,
                                 double half_length_m);

class TaskController {
 public:
  // Throws std::runtime_error when an LQR design fails.
  TaskController(const TaskControlSettings& settings, const model::VehicleLimits& limits);

  // The command of a task that flies_law(), and what the runtime keeps of it.
  TaskCommand command(TaskState& state, const TaskFrame& frame, const FlownThrow& flown) const;

  const TaskControlSettings& settings() const { return settings_; }

 private:
  model::VehicleInput hover(TaskState& state, const TaskFrame& frame, bool integrate) const;
  TaskControlSettings settings_;
  model::VehicleLimits limits_;
  control::LqrGain hover_;
  control::LqrGain catch_;
  control::LqrGain balancing_;
};

}  // namespace gs::runtime
