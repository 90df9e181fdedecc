// What `groundstation watch` prints (groundstation/service/status_view.hpp), from canned telemetry
// and events: each vehicle's link, task, mode and estimate, the pole and its catch prediction,
// the latest events, and what is said when something was never heard.
#include "groundstation/service/status_view.hpp"

#include <catch2/catch.hpp>
#include <cstring>
#include <string>

#include "groundstation/dds/mocap_conversion.hpp"
#include "groundstation/mission/vehicle_sequencer.hpp"

using gs::service::render_status;
using gs::service::StatusView;

namespace {

gs::dds::VehicleTelemetry vehicle(std::uint8_t id, std::uint8_t link, double x) {
  gs::dds::VehicleTelemetry t{};
  t.vehicle = id;
  t.stamp = gs::dds::ros_time(1'000'000'000);
  t.link = link;
  t.task = static_cast<std::uint8_t>(gs::mission::Task::hover);
  t.vehicle_mode = 2;  // flying
  t.estimate_valid = true;
  t.position = {x, 0.5, 1.25};
  t.velocity = {3.0, 4.0, 0.0};
  t.orientation = {0.0, 0.0, 0.0, 1.0};
  return t;
}

gs::dds::Event event(std::int64_t stamp_ns, std::uint8_t kind, std::uint8_t id, const char* detail) {
  gs::dds::Event e{};
  e.stamp = gs::dds::ros_time(stamp_ns);
  e.kind = kind;  // any value, as from the wire
  e.vehicle = id;
  std::strncpy(e.detail, detail, sizeof e.detail - 1);
  return e;
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace

TEST_CASE("Nothing heard: each vehicle and the pole say so") {
  const StatusView view;
  CHECK_FALSE(view.has_telemetry());
  CHECK_FALSE(view.has_all_telemetry());
  const std::string text = render_status(view);
  CHECK(contains(text, "vehicle 1  no telemetry"));
  CHECK(contains(text, "vehicle 2  no telemetry"));
  CHECK(contains(text, "pole       no telemetry"));
  CHECK(contains(text, "events     none yet"));
}

TEST_CASE("Vehicles, the pole in flight with its catch prediction, and the latest events") {
  StatusView view;
  view.add(vehicle(1, gs::dds::link_state::kUp, -1.0));
  view.add(vehicle(2, gs::dds::link_state::kLost, 1.0));
  view.add(vehicle(7, gs::dds::link_state::kUp, 9.0));  // not of the act: ignored
  gs::dds::PoleTelemetry pole{};
  pole.stamp = gs::dds::ros_time(2'000'000'000);
  pole.estimate_valid = true;
  pole.mode = gs::dds::pole_mode::kFree;
  pole.position = {0.25, 0.0, 3.5};
  pole.catch_predicted = true;
  pole.catch_stamp = gs::dds::ros_time(2'500'000'000);
  pole.catch_point = {0.75, -0.25, 2.0};
  pole.catch_vehicle = 2;
  view.pole = pole;
  for (int i = 0; i < 8; ++i)
    view.add(event(i * 1'000'000'000LL, gs::dds::event_kind::kTaskChange, 1, "take_off -> hover"));
  // ROS time: the system clock's time of day, UTC (2026-12-07 13:04:59.250).
  view.add(event(1'796'648'699'250'000'000, gs::dds::event_kind::kCommandAccepted, 0,
                 "command 3: throw: attempt 1"));

  REQUIRE(view.has_telemetry());
  CHECK(view.has_all_telemetry());
  const std::string text = render_status(view);
  CHECK(contains(text, "vehicle 1  link up"));
  CHECK(contains(text, "vehicle 2  link LOST"));
  CHECK_FALSE(contains(text, "vehicle 7"));
  CHECK(contains(text, "task hover"));
  CHECK(contains(text, "vehicle flying"));
  CHECK(contains(text, "at  -1.00   0.50   1.25 m  speed  5.00 m/s"));
  CHECK(contains(text, "catch by vehicle 2 in 0.50 s at 0.75 -0.25 2.00 m"));
  CHECK(contains(text, "accepted"));
  CHECK(contains(text, "13:04:59.250  accepted"));
  CHECK(contains(text, "00:00:07.000  task change"));
  CHECK(contains(text, "command 3: throw: attempt 1"));
  REQUIRE(view.events.size() == StatusView::kEvents);  // only the latest kept
  CHECK(view.events.back().kind == gs::dds::event_kind::kCommandAccepted);
  CHECK(view.events.front().stamp_ns == 3'000'000'000);  // events at 3..7 s and the last
}

TEST_CASE("Values out of range are shown as numbers, not indexed past a table") {
  StatusView view;
  gs::dds::VehicleTelemetry t = vehicle(1, 17, 0.0);
  t.task = 200;
  t.vehicle_mode = 99;
  t.estimate_valid = false;
  view.add(t);
  CHECK(view.has_telemetry());
  CHECK_FALSE(view.has_all_telemetry());  // vehicle 2 and the pole not heard
  view.add(event(0, 50, 0, "?"));
  gs::dds::PoleTelemetry pole{};
  pole.estimate_valid = true;
  pole.mode = 9;
  view.pole = pole;
  const std::string text = render_status(view);
  CHECK(contains(text, "link unknown"));
  CHECK(contains(text, "task 200"));
  CHECK(contains(text, "mode 99"));
  CHECK(contains(text, "no estimate"));
  CHECK(contains(text, "event 50"));
  CHECK(contains(text, "pole       mode 9"));
}
