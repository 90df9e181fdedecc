#include "groundstation/runtime/task_control.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "groundstation/control/balancing_lqr.hpp"
#include "groundstation/control/hover_lqr.hpp"
#include "groundstation/planning/throw_command.hpp"
#include "groundstation/planning/throw_correction.hpp"
#include "pa/constants.hpp"

namespace gs::runtime {
namespace {

using mission::Task;

control::LqrGain designed(const control::LqrGain& gain) {
  if (!gain.ok) throw std::runtime_error("the LQR design failed");
  return gain;
}

}  // namespace

bool flies_law(Task task) {
  return task != Task::landing && task != Task::failsafe && task != Task::parked && task != Task::arming;
}

std::optional<model::VehicleInput> fixed_command(Task task) {
  if (task != Task::parked && task != Task::arming) return std::nullopt;
  model::VehicleInput idle;
  idle.a_q_mps2 = 0.0;
  return idle;
}

double tilt_rad(const model::PoleState& s) { return std::acos(std::min(1.0, std::abs(s.n.z()))); }

// A pole caught 1.6 cm off the plate's centre, balanced about the centre, read as a 0.025 rad
// tilt, which the balancing LQR held against a 0.46 m position error (measured: the catcher of a
// pass could not reach its throw's origin). The throw flies about the end where it rested as the
// throw started, carried with the plate (the filter's offset moves while the throw accelerates:
// flown about the moving end, the learnt throw's error after 10 throws was 0.105 against 0.078,
// throw_learning_test).
control::Pivot resting_pivot(const estimation::PlateKinematics& plate, const model::PoleState& pole,
                             double half_length_m) {
  const Eigen::Vector3d a = pole.p_m + half_length_m * pole.n, b = pole.p_m - half_length_m * pole.n;
  return {(a - plate.p_m).norm() < (b - plate.p_m).norm() ? a : b, plate.v_mps};
}

Eigen::Vector3d resting_offset_m(const estimation::PlateKinematics& plate, const model::PoleState& pole,
                                 double half_length_m) {
  return plate.inertial_from_body.transpose() * (resting_pivot(plate, pole, half_length_m).p_m - plate.p_m);
}

TaskController::TaskController(const TaskControlSettings& settings, const model::VehicleLimits& limits)
    : settings_(settings),
      limits_(limits),
      hover_(designed(control::hover_lqr())),
      catch_(designed(control::hover_lqr(control::catch_lqr_weights()))),
      balancing_(designed(control::balancing_lqr())) {}

// The integral shifts the LQR's reference position (p_ref = set point + k_i int e): a constant
// force offset then leaves no position error, whatever the controller (hover or balancing).
model::VehicleInput TaskController::hover(TaskState& s, const TaskFrame& f, bool integrate) const {
  if (integrate)
    control::integrate_position_error(s.integral, s.set_point, s.target_m, f.vehicle.state.p_m, f.dt_s,
                                      settings_.position_integral_limit_ms);
  control::HoverReference reference;
  reference.position_m = s.set_point.position_m + settings_.position_integral_gain * s.integral;
  reference.velocity_mps = s.set_point.velocity_mps;
  return control::hover_law(hover_, f.vehicle.state, reference);
}

TaskCommand TaskController::command(TaskState& s, const TaskFrame& f, const FlownThrow& flown) const {
  const TaskControlSettings& c = settings_;
  const estimation::VehicleEstimate& e = f.vehicle;
  const double L = f.half_length_m;
  const auto clamped = [&](const model::VehicleInput& u) { return control::clamp_input(u, limits_); };
  TaskCommand out;
  switch (f.task) {
    case Task::take_off:
    case Task::hover:
    case Task::wait:
    case Task::retreat:
    case Task::clear:
    case Task::rebalance:
    case Task::descend: {
      if (f.task == Task::wait) s.target_m = f.waiting_target_m;
      control::move_set_point(s.set_point, s.target_m, e.state.p_m, f.dt_s, c.carrot);
      const bool on_floor = f.task == Task::take_off && e.state.p_m.z() <= c.take_off_integral_height_m;
      model::VehicleInput u = hover(s, f, !on_floor);
      if (f.task == Task::rebalance) u.a_q_mps2 += c.pole_weight_mps2;
      if (f.task == Task::take_off) {
        // The ramp grows on the floor and gives way in the air to the integral and the measured
        // thrust gain, which take over from it within a second.
        const bool stuck = on_floor && f.now_s - f.task_since_s > c.take_off_ramp_after_s;
        s.take_off_ramp_mps2 =
            std::clamp(s.take_off_ramp_mps2 + (stuck ? 1.0 : -1.0) * c.take_off_ramp_mps3 * f.dt_s, 0.0,
                       limits_.a_q_max_mps2);
        u.a_q_mps2 += s.take_off_ramp_mps2;
      }
      out.input = clamped(control::limit_tilt(u, e.state, c.tilt_limit));
      break;
    }
    case Task::balance: {
      control::move_set_point(s.set_point, s.target_m, e.state.p_m, f.dt_s, c.carrot);
      out.pole_settled = f.pole.valid && tilt_rad(f.pole.state) < c.balance_settled_rad;
      control::integrate_position_error(s.integral, s.set_point, s.target_m, e.state.p_m, f.dt_s,
                                        c.position_integral_limit_ms);
      const Eigen::Vector3d plate_offset = pa::kPlateHeightAboveCg_m * Eigen::Vector3d::UnitZ();
      out.input = clamped(control::limit_tilt(
          control::balance_law(balancing_, resting_pivot(f.plate, f.pole.state, L), e.state, f.pole.state, L,
                               s.set_point.position_m + plate_offset + c.position_integral_gain * s.integral,
                               s.set_point.velocity_mps, c.pole_weight_mps2),
          e.state, c.tilt_limit));
      break;
    }
    case Task::throwing: {
      const double duration_s = flown.trajectory->duration_s();
      const double tau = std::min(f.t_act_s - f.task_since_s, duration_s);
      // The learnt throw (throw_learning.hpp) is the Fig. 5 throw's only: a throw to a target is
      // planned anew each time. The pole is flown about the end it rested on as the throw
      // started, turned with the plate (planning/throw_command.hpp says what the plate's centre
      // cost); taken as the throw starts, since the filter's estimate of it moves while the
      // throw accelerates (the learnt throw's error grew, throw_learning_test).
      const model::PlanarState<double> shift =
          flown.correction ? planning::reference_shift(flown.correction->end_shift, tau, duration_s)
                           : model::PlanarState<double>::Zero();
      const planning::ThrowStep step = planning::throw_step(
          *flown.tracker, balancing_, tau, flown.frame, control::Pivot{f.plate.p_m, f.plate.v_mps},
          f.plate.inertial_from_body * flown.resting_offset_m, e.state, f.pole.state, L, shift, limits_,
          f.motor_lead_s);
      if (tau >= duration_s - c.launch_state_window_s) out.throw_end = ThrowEnd{tau, step.state};
      out.input = clamped(step.input);
      break;
    }
    case Task::release: {
      const Eigen::Vector3d pitch_back = flown.frame.body_rates_to_vehicle(
          Eigen::Vector3d(0.0, flown.trajectory->input.back()(model::planar::kPitchRate), 0.0));
      out.input = clamped(control::release_law(e.state, f.t_act_s - f.task_since_s, c.release_pitch_s,
                                               pitch_back, c.release_level_gain_per_s, limits_.a_q_min_mps2));
      break;
    }
    case Task::catching: {
      if (!flown.catch_trajectory) {
        out.input = clamped(hover(s, f, false));
        break;
      }
      planning::CatchReference ref = flown.catch_trajectory->reference(f.t_act_s - flown.catch_start_s);
      if (flown.catch_height_shift) ref = planning::shifted(ref, flown.catch_height_shift->at(f.t_act_s));
      // The catch LQR (the hover's, stiffer in xy: control::catch_lqr_weights) about the
      // reference's state with its nominal inputs (46), (47) as feed forward: a time-varying
      // reference tracked with hover-designed gains, which hold across the
      // manoeuvre's tilts (at most atan(a_max / g) ~ 23 degrees plus the xy correction's). The
      // integral learnt while waiting stays in force, frozen.
      control::HoverReference reference;
      reference.position_m = ref.position_m + c.position_integral_gain * s.integral;
      reference.velocity_mps = ref.velocity_mps;
      reference.roll_rad = ref.roll_rad;
      reference.pitch_rad = ref.pitch_rad;
      reference.yaw_rad = ref.yaw_rad;
      reference.thrust_mps2 = ref.thrust_mps2;
      reference.body_rates_radps = ref.body_rates_radps;
      s.set_point.position_m = ref.position_m;
      out.input = clamped(control::hover_law(catch_, e.state, reference));
      break;
    }
    default: break;
  }
  return out;
}

}  // namespace gs::runtime
