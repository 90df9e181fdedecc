// The task controllers (groundstation/runtime/task_control.hpp): which tasks fly a law, and for
// each the law and the state it carries: the carrot, the integral, the take-off ramp, the pole's
// weight, the settled pole, the throw's end, the release and the catch's reference.
#include <catch2/catch.hpp>

#include <cmath>

#include "groundstation/planning/throw_book.hpp"
#include "groundstation/runtime/task_control.hpp"

namespace {

using gs::mission::Task;
using gs::runtime::FlownThrow;
using gs::runtime::TaskCommand;
using gs::runtime::TaskController;
using gs::runtime::TaskFrame;
using gs::runtime::TaskState;

const gs::model::VehicleLimits kLimits{1.0, 20.0, 10.0};
const gs::runtime::TaskControlSettings kSettings;

// A vehicle at rest at `p_m`, in `task` since t = 0, at t = 5 s.
TaskFrame at_rest(Task task, const Eigen::Vector3d& p_m) {
  TaskFrame f;
  f.task = task;
  f.now_s = 5.0;
  f.t_act_s = 5.012;
  f.dt_s = 0.005;
  f.vehicle.state.p_m = p_m;
  f.plate.p_m = p_m + pa::kPlateHeightAboveCg_m * Eigen::Vector3d::UnitZ();
  f.half_length_m = 0.26;
  return f;
}

// On its target, its carrot there.
TaskState holding(const Eigen::Vector3d& p_m) {
  TaskState s;
  s.target_m = p_m;
  s.set_point.position_m = p_m;
  s.set_point.valid = true;
  return s;
}

}  // namespace

TEST_CASE("Which tasks fly a law: none landing or in failsafe, zero thrust parked and arming") {
  for (Task t : {Task::landing, Task::failsafe}) {
    CHECK_FALSE(gs::runtime::flies_law(t));
    CHECK_FALSE(gs::runtime::fixed_command(t));
  }
  for (Task t : {Task::parked, Task::arming}) {
    CHECK_FALSE(gs::runtime::flies_law(t));
    REQUIRE(gs::runtime::fixed_command(t));
    CHECK(gs::runtime::fixed_command(t)->a_q_mps2 == 0.0);
    CHECK(gs::runtime::fixed_command(t)->omega_radps.isZero());
  }
  for (Task t : {Task::take_off, Task::hover, Task::balance, Task::throwing, Task::release, Task::retreat,
                 Task::wait, Task::catching, Task::rebalance, Task::clear, Task::descend}) {
    CHECK(gs::runtime::flies_law(t));
    CHECK_FALSE(gs::runtime::fixed_command(t));
  }
}

TEST_CASE("The pole's tilt either end up, and the end it rests on") {
  gs::model::PoleState pole;
  CHECK(gs::runtime::tilt_rad(pole) == 0.0);
  pole.n = -Eigen::Vector3d::UnitZ();
  CHECK(gs::runtime::tilt_rad(pole) == 0.0);
  pole.n = Eigen::Vector3d(std::sin(0.2), 0.0, std::cos(0.2));
  CHECK(gs::runtime::tilt_rad(pole) == Approx(0.2));
  gs::estimation::PlateKinematics plate;
  plate.p_m = Eigen::Vector3d(0.0, 0.0, 1.0);
  plate.v_mps = Eigen::Vector3d(0.3, 0.0, 0.0);
  pole.n = Eigen::Vector3d::UnitZ();
  pole.p_m = Eigen::Vector3d(0.01, 0.0, 1.26);
  const gs::control::Pivot pivot = gs::runtime::resting_pivot(plate, pole, 0.26);
  CHECK(pivot.p_m.isApprox(Eigen::Vector3d(0.01, 0.0, 1.0)));
  CHECK(pivot.v_mps == plate.v_mps);
}

TEST_CASE("The resting offset: from the plate's centre to the pole's nearer end") {
  gs::estimation::PlateKinematics plate;
  plate.p_m = Eigen::Vector3d(1.0, 2.0, 1.0);
  gs::model::PoleState pole;
  pole.n = -Eigen::Vector3d::UnitZ();  // either end up
  pole.p_m = Eigen::Vector3d(1.02, 2.0, 1.26);
  CHECK(gs::runtime::resting_offset_m(plate, pole, 0.26).isApprox(Eigen::Vector3d(0.02, 0.0, 0.0)));
  pole.p_m = Eigen::Vector3d(1.0, 1.97, 0.74);  // hanging below the plate: its upper end
  CHECK(gs::runtime::resting_offset_m(plate, pole, 0.26).isApprox(Eigen::Vector3d(0.0, -0.03, 0.0)));
  // In the plate's axes: a plate pitched 0.3 rad with the pole's end 2 cm along its own x.
  plate.inertial_from_body = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()).toRotationMatrix();
  pole.n = plate.inertial_from_body.col(2);
  pole.p_m = plate.p_m + plate.inertial_from_body * Eigen::Vector3d(0.02, 0.0, 0.0) + 0.26 * pole.n;
  CHECK(gs::runtime::resting_offset_m(plate, pole, 0.26).isApprox(Eigen::Vector3d(0.02, 0.0, 0.0)));
}

TEST_CASE("Hovering on its target at rest: g, level, and the integral untouched") {
  const TaskController control(kSettings, kLimits);
  const Eigen::Vector3d p(0.0, 0.0, 1.0);
  TaskState s = holding(p);
  const TaskCommand c = control.command(s, at_rest(Task::hover, p), {});
  REQUIRE(c.input);
  CHECK(c.input->a_q_mps2 == Approx(pa::kGravity_mps2));
  CHECK(c.input->omega_radps.norm() == Approx(0.0).margin(1e-9));
  CHECK(s.integral.isZero());
  CHECK_FALSE(c.pole_settled);
  CHECK_FALSE(c.throw_end);
}

TEST_CASE("Hovering below its set point: the integral grows and the thrust rises") {
  const TaskController control(kSettings, kLimits);
  TaskState s = holding(Eigen::Vector3d(0.0, 0.0, 1.0));
  const TaskCommand c = control.command(s, at_rest(Task::hover, Eigen::Vector3d(0.0, 0.0, 0.9)), {});
  CHECK(s.integral.z() == Approx(0.1 * 0.005));
  CHECK(c.input->a_q_mps2 > pa::kGravity_mps2);
}

TEST_CASE("Hovering, however far its set point, never tilts on towards more than the tilt limit") {
  // A vehicle already at the limit (0.7 rad of pitch), moving away from its set point at 5 m/s:
  // the hover law alone would pitch on to brake; the limit lets it pitch only back.
  const TaskController control(kSettings, kLimits);
  TaskState s = holding(Eigen::Vector3d(0.0, 0.0, 3.0));
  for (const Task task : {Task::hover, Task::wait, Task::retreat, Task::clear, Task::rebalance}) {
    TaskFrame f = at_rest(task, Eigen::Vector3d(3.6, 0.0, 3.0));
    f.waiting_target_m = s.target_m;
    f.vehicle.state.v_mps = Eigen::Vector3d(5.0, 0.0, 0.0);
    f.vehicle.state.theta_rad = -kSettings.tilt_limit.max_tilt_rad;
    const TaskCommand braking = control.command(s, f, {});
    CHECK(braking.input->omega_radps.y() >= 0.0);
    f.vehicle.state.theta_rad = 0.0;  // level, it may tilt to brake
    CHECK(control.command(s, f, {}).input->omega_radps.y() < 0.0);
  }
}

TEST_CASE("Waiting flies to the waiting point the frame gives") {
  const TaskController control(kSettings, kLimits);
  TaskState s = holding(Eigen::Vector3d(0.0, 0.0, 1.0));
  TaskFrame f = at_rest(Task::wait, Eigen::Vector3d(0.0, 0.0, 1.0));
  f.waiting_target_m = Eigen::Vector3d(2.0, 0.0, 1.5);
  control.command(s, f, {});
  CHECK(s.target_m == f.waiting_target_m);
  CHECK(s.set_point.velocity_mps.x() > 0.0);  // the carrot sets off towards it
}

TEST_CASE("Rebalancing carries the pole's weight on top of the hover law") {
  const TaskController control(kSettings, kLimits);
  const Eigen::Vector3d p(0.0, 0.0, 1.0);
  TaskState hover = holding(p), rebalance = holding(p);
  const double a_hover = control.command(hover, at_rest(Task::hover, p), {}).input->a_q_mps2;
  const double a_rebalance = control.command(rebalance, at_rest(Task::rebalance, p), {}).input->a_q_mps2;
  CHECK(a_rebalance - a_hover == Approx(kSettings.pole_weight_mps2));
}

TEST_CASE("Take-off: no integral on the floor; stuck there, the thrust ramps up, in the air back down") {
  const TaskController control(kSettings, kLimits);
  const Eigen::Vector3d floor(0.0, 0.0, 0.1), target(0.0, 0.0, 1.0);
  TaskState s = holding(floor);
  s.target_m = target;
  TaskFrame f = at_rest(Task::take_off, floor);
  f.task_since_s = f.now_s - kSettings.take_off_ramp_after_s + 0.001;  // not yet stuck
  control.command(s, f, {});
  CHECK(s.take_off_ramp_mps2 == 0.0);
  CHECK(s.integral.isZero());
  f.task_since_s = f.now_s - kSettings.take_off_ramp_after_s - 0.001;  // stuck
  const double a0 = control.command(s, f, {}).input->a_q_mps2;
  CHECK(s.take_off_ramp_mps2 == Approx(kSettings.take_off_ramp_mps3 * f.dt_s));
  const double a1 = control.command(s, f, {}).input->a_q_mps2;
  CHECK(s.take_off_ramp_mps2 == Approx(2.0 * kSettings.take_off_ramp_mps3 * f.dt_s));
  CHECK(a1 > a0);
  CHECK(s.integral.isZero());
  TaskFrame air = at_rest(Task::take_off, Eigen::Vector3d(0.0, 0.0, 0.5));
  air.task_since_s = f.task_since_s;
  control.command(s, air, {});
  CHECK(s.take_off_ramp_mps2 == Approx(kSettings.take_off_ramp_mps3 * f.dt_s));
  control.command(s, air, {});
  control.command(s, air, {});
  CHECK(s.take_off_ramp_mps2 == 0.0);  // never below zero
}

TEST_CASE("Balancing reports whether the pole stands settled, by balance_settled_rad") {
  const TaskController control(kSettings, kLimits);
  const Eigen::Vector3d p(0.0, 0.0, 2.0);
  TaskState s = holding(p);
  TaskFrame f = at_rest(Task::balance, p);
  f.pole.valid = true;
  f.pole.state.p_m = f.plate.p_m + f.half_length_m * Eigen::Vector3d::UnitZ();
  TaskCommand c = control.command(s, f, {});
  REQUIRE(c.pole_settled);
  CHECK(*c.pole_settled);
  REQUIRE(c.input);
  CHECK(c.input->a_q_mps2 == Approx(pa::kGravity_mps2 + kSettings.pole_weight_mps2));
  const double tilt = kSettings.balance_settled_rad + 0.001;
  f.pole.state.n = Eigen::Vector3d(std::sin(tilt), 0.0, std::cos(tilt));
  c = control.command(s, f, {});
  CHECK_FALSE(*c.pole_settled);
  f.pole.valid = false;  // no estimate: not settled
  CHECK_FALSE(*control.command(s, f, {}).pole_settled);
}

TEST_CASE("Release: minimum thrust, the plate pitched back at the launch rate, then levelled") {
  const gs::planning::ThrowBook book(kLimits, {});
  const TaskController control(kSettings, kLimits);
  FlownThrow flown;
  flown.trajectory = &book.plan().trajectory;
  flown.tracker = &book.tracker();
  TaskState s;
  TaskFrame f = at_rest(Task::release, Eigen::Vector3d(0.0, 0.0, 2.0));
  f.vehicle.state.theta_rad = 0.1;
  f.task_since_s = f.t_act_s - 0.5 * kSettings.release_pitch_s;
  TaskCommand c = control.command(s, f, flown);
  CHECK(c.input->a_q_mps2 == kLimits.a_q_min_mps2);
  const double launch_rate = book.plan().trajectory.input.back()(gs::model::planar::kPitchRate);
  CHECK(c.input->omega_radps.norm() == Approx(std::min(std::abs(launch_rate), kLimits.omega_max_radps)));
  f.task_since_s = f.t_act_s - kSettings.release_pitch_s - 0.001;
  c = control.command(s, f, flown);
  CHECK(c.input->omega_radps.y() == Approx(-kSettings.release_level_gain_per_s * 0.1));
}

TEST_CASE("Throwing tracks the plan and reports its end state only within the window before T") {
  const gs::planning::ThrowBook book(kLimits, {});
  const TaskController control(kSettings, kLimits);
  FlownThrow flown;
  flown.trajectory = &book.plan().trajectory;
  flown.tracker = &book.tracker();
  flown.frame = gs::control::ThrowFrame{Eigen::Vector3d(0.0, 0.0, 2.0), 0.0};
  const double T = book.plan().trajectory.duration_s();
  TaskState s;
  TaskFrame f = at_rest(
      Task::throwing, Eigen::Vector3d(0.0, 0.0, 2.0) - pa::kPlateHeightAboveCg_m * Eigen::Vector3d::UnitZ());
  f.pole.valid = true;
  f.pole.state.p_m = f.plate.p_m + f.half_length_m * Eigen::Vector3d::UnitZ();
  f.task_since_s = f.t_act_s - (T - kSettings.launch_state_window_s - 0.001);
  TaskCommand c = control.command(s, f, flown);
  REQUIRE(c.input);
  CHECK_FALSE(c.throw_end);
  f.task_since_s = f.t_act_s - (T - kSettings.launch_state_window_s + 0.001);
  c = control.command(s, f, flown);
  REQUIRE(c.throw_end);
  CHECK(c.throw_end->tau_s == Approx(T - kSettings.launch_state_window_s + 0.001));
  f.task_since_s = f.t_act_s - (T + 1.0);  // past T: held at T
  c = control.command(s, f, flown);
  CHECK(c.throw_end->tau_s == T);
  CHECK(c.input->a_q_mps2 >= kLimits.a_q_min_mps2);
  CHECK(c.input->a_q_mps2 <= kLimits.a_q_max_mps2);
}

TEST_CASE("Catching with no manoeuvre planned yet holds without integrating") {
  const TaskController control(kSettings, kLimits);
  const Eigen::Vector3d p(0.0, 0.0, 1.0);
  TaskState s = holding(Eigen::Vector3d(0.0, 0.0, 1.1));
  s.integral = Eigen::Vector3d(0.0, 0.0, 0.2);
  const TaskCommand c = control.command(s, at_rest(Task::catching, p), {});
  REQUIRE(c.input);
  CHECK(s.integral == Eigen::Vector3d(0.0, 0.0, 0.2));  // frozen
  CHECK(s.set_point.position_m.z() == 1.1);             // the carrot does not move either
}
