// The tasks' entry actions (groundstation/runtime/task_entry.hpp): for each task what it does to
// the vehicle's laws and requests, and the command it sends.
#include <catch2/catch.hpp>

#include "groundstation/runtime/task_entry.hpp"

namespace {

using gs::mission::Reason;
using gs::mission::Task;
using gs::runtime::enter_task;
using gs::runtime::TaskEntry;
using gs::runtime::TaskEntryContext;
using gs::runtime::TaskState;
using pa::proto::CommandCode;
namespace c = gs::mission::condition;

const gs::runtime::TaskEntrySettings kSettings;
constexpr std::uint32_t kAllRequests =
    c::request_take_off | c::request_throw | c::request_catch | c::request_abort | c::request_land;

// A vehicle at (1, 2, 1.5) whose laws carry an integral, a moving carrot and a target elsewhere.
TaskState flying() {
  TaskState s;
  s.target_m = Eigen::Vector3d(0.0, 0.0, 2.0);
  s.set_point.position_m = Eigen::Vector3d(0.5, 1.0, 1.8);
  s.set_point.velocity_mps = Eigen::Vector3d(0.2, 0.0, 0.0);
  s.set_point.valid = true;
  s.integral = Eigen::Vector3d(0.1, 0.1, 0.1);
  s.take_off_ramp_mps2 = 2.0;
  return s;
}

TaskEntryContext here() {
  TaskEntryContext context;
  context.here_m = Eigen::Vector3d(1.0, 2.0, 1.5);
  context.vehicle_mode = pa::proto::Mode::armed;
  context.retreat_target_m = Eigen::Vector3d(0.0, 0.0, 1.9);
  context.catch_target_xy_m = Eigen::Vector2d(1.0, 1.0);
  return context;
}

struct Entered {
  TaskState laws;
  std::uint32_t requests = kAllRequests;
  TaskEntry entry;
};
Entered enter(Task task, const TaskEntryContext& context = here()) {
  Entered e{flying(), kAllRequests, {}};
  e.entry = enter_task(task, e.laws, e.requests, context, kSettings);
  return e;
}

}  // namespace

TEST_CASE("Every entry resets the integral and the carrot's velocity") {
  for (int t = 0; t < gs::mission::kTaskCount; ++t) {
    const Entered e = enter(static_cast<Task>(t));
    CAPTURE(gs::mission::task_name(static_cast<Task>(t)));
    CHECK(e.laws.integral.isZero());
    CHECK(e.laws.set_point.velocity_mps.isZero());
  }
}

TEST_CASE("Which requests each entry clears, and which commands it sends") {
  struct Row {
    Task task;
    std::uint32_t cleared;
    std::optional<CommandCode> command;
  };
  const Row rows[] = {
      {Task::parked, c::request_land, std::nullopt},
      {Task::arming, c::request_take_off, CommandCode::arm},
      {Task::take_off, 0, std::nullopt},
      {Task::hover, 0, std::nullopt},
      {Task::balance, 0, std::nullopt},
      {Task::throwing, c::request_throw, std::nullopt},
      {Task::release, c::request_abort, std::nullopt},
      {Task::retreat, 0, std::nullopt},
      {Task::wait, 0, std::nullopt},
      {Task::catching, 0, CommandCode::expect_catch},
      {Task::rebalance, 0, CommandCode::catch_handled},
      {Task::clear, c::request_abort | c::request_catch, std::nullopt},
      {Task::landing, c::request_land, CommandCode::land},
      {Task::failsafe, 0, std::nullopt},
      {Task::descend, c::request_land, std::nullopt},
  };
  REQUIRE(std::size(rows) == static_cast<std::size_t>(gs::mission::kTaskCount));
  for (const Row& row : rows) {
    CAPTURE(gs::mission::task_name(row.task));
    const Entered e = enter(row.task);
    CHECK(gs::mission::condition_names(kAllRequests & ~e.requests) ==
          gs::mission::condition_names(row.cleared));
    CHECK(e.entry.command.has_value() == row.command.has_value());
    if (row.command && e.entry.command) CHECK(e.entry.command->code == *row.command);
    CHECK_FALSE(e.entry.arm_after_disarm);
    CHECK_FALSE(e.entry.start_identification);
  }
}

TEST_CASE("Arming a vehicle that landed disarms it first") {
  TaskEntryContext context = here();
  context.vehicle_mode = pa::proto::Mode::landed;
  const Entered e = enter(Task::arming, context);
  REQUIRE(e.entry.command);
  CHECK(e.entry.command->code == CommandCode::disarm);
  CHECK(e.entry.arm_after_disarm);
}

TEST_CASE("Parked and failsafe drop the set point; take-off climbs from where it stands") {
  CHECK_FALSE(enter(Task::parked).laws.set_point.valid);
  CHECK_FALSE(enter(Task::failsafe).laws.set_point.valid);
  const Entered e = enter(Task::take_off);
  CHECK(e.laws.target_m == Eigen::Vector3d(1.0, 2.0, kSettings.take_off_height_m));
  CHECK(e.laws.set_point.position_m == here().here_m);
  CHECK(e.laws.take_off_ramp_mps2 == 0.0);
}

TEST_CASE("A landing descends straight down to the hand-over height, never up") {
  const Entered high = enter(Task::descend);
  CHECK(high.laws.target_m == Eigen::Vector3d(1.0, 2.0, kSettings.land_handover_height_m));
  CHECK(high.laws.set_point.position_m == here().here_m);
  CHECK(high.laws.set_point.valid);
  TaskEntryContext low = here();
  low.here_m.z() = 0.06;  // a take-off still on its feet
  CHECK(enter(Task::descend, low).laws.target_m == low.here_m);
}

TEST_CASE("LAND carries the vertical speed motion capture measures, in mm/s within the protocol's bound") {
  TaskEntryContext context = here();
  context.vertical_speed_mps = -0.1234;
  const Entered e = enter(Task::landing, context);
  REQUIRE(e.entry.command);
  CHECK(e.entry.command->code == CommandCode::land);
  CHECK(e.entry.command->argument == -123);
  context.vertical_speed_mps = 9.0;  // an estimate gone wild is sent as the bound, never past it
  CHECK(enter(Task::landing, context).entry.command->argument == pa::proto::kLandSpeedMax_mmps);
  context.vertical_speed_mps = -9.0;
  CHECK(enter(Task::landing, context).entry.command->argument == -pa::proto::kLandSpeedMax_mmps);
}

TEST_CASE("Hover and balance keep a valid carrot; hover after take-off identifies the motors") {
  CHECK(enter(Task::hover).laws.set_point.position_m == flying().set_point.position_m);
  CHECK(enter(Task::balance).laws.set_point.position_m == flying().set_point.position_m);
  TaskEntryContext context = here();
  context.identify_motors = true;
  CHECK_FALSE(enter(Task::hover, context).entry.start_identification);  // not airborne
  context.reason = Reason::airborne;
  CHECK(enter(Task::hover, context).entry.start_identification);
  context.identify_motors = false;
  CHECK_FALSE(enter(Task::hover, context).entry.start_identification);
  // Without a carrot they hold where the vehicle is.
  Entered e{flying(), 0, {}};
  e.laws.set_point.valid = false;
  enter_task(Task::balance, e.laws, e.requests, here(), kSettings);
  CHECK(e.laws.set_point.valid);
  CHECK(e.laws.set_point.position_m == here().here_m);
}

TEST_CASE("Retreat flies to the throw's origin; rebalance holds where the pole was caught") {
  const Entered retreat = enter(Task::retreat);
  CHECK(retreat.laws.target_m == here().retreat_target_m);
  CHECK(retreat.laws.set_point.position_m == here().here_m);
  const Entered rebalance = enter(Task::rebalance);
  CHECK(rebalance.laws.target_m == here().here_m);
  CHECK(rebalance.laws.set_point.position_m == here().here_m);
}

TEST_CASE("EXPECT_CATCH carries the catch's window in milliseconds, within the firmware's bounds") {
  TaskEntryContext context = here();
  context.catch_window_s = 2.3456;
  CHECK(enter(Task::catching, context).entry.command->argument == 2345);
  context.catch_window_s = 0.01;
  CHECK(enter(Task::catching, context).entry.command->argument == 100);
  context.catch_window_s = 60.0;
  CHECK(enter(Task::catching, context).entry.command->argument == 10000);
}

TEST_CASE("Clear flies sideways away from where the pole comes down, at the same height") {
  const Entered e = enter(Task::clear);  // from (1, 2): away from (1, 1) is +y
  CHECK(e.laws.target_m.isApprox(Eigen::Vector3d(1.0, 2.0 + kSettings.clear_distance_m, 1.5)));
  TaskEntryContext context = here();
  context.catch_target_xy_m = Eigen::Vector2d(2.0, 2.0);  // away is -x
  CHECK(enter(Task::clear, context)
            .laws.target_m.isApprox(Eigen::Vector3d(1.0 - kSettings.clear_distance_m, 2.0, 1.5)));
  context.catch_target_xy_m = Eigen::Vector2d(1.05, 2.0);  // right above it: along +y
  CHECK(enter(Task::clear, context)
            .laws.target_m.isApprox(Eigen::Vector3d(1.0, 2.0 + kSettings.clear_distance_m, 1.5)));
}
