// What `groundstation watch` shows: the latest telemetry of each vehicle and of the pole, and the
// latest events, read from the ground station's DDS topics and rendered as a few lines of text.
#pragma once

#include <array>
#include <chrono>
#include <cstddef>
#include <deque>
#include <optional>
#include <string>

#include "groundstation/dds/dds.hpp"

namespace gs::service {

struct EventLine {
  std::int64_t stamp_ns = 0;                         // ROS time
  std::uint8_t kind = dds::event_kind::kTaskChange;  // as on the wire: any value
  std::uint8_t vehicle = 0;
  std::string detail;
};

struct StatusView {
  static constexpr std::size_t kEvents = 6;                      // the latest events shown
  std::array<std::optional<dds::VehicleTelemetry>, 2> vehicles;  // by pa::act_slot()
  std::optional<dds::PoleTelemetry> pole;
  std::deque<EventLine> events;  // oldest first

  bool has_telemetry() const { return pole || vehicles[0] || vehicles[1]; }
  bool has_all_telemetry() const { return pole && vehicles[0] && vehicles[1]; }
  void add(const dds::VehicleTelemetry& telemetry);  // other vehicles than the act's are ignored
  void add(const dds::Event& event);
};

std::string event_kind_name(std::uint8_t kind);
// A ROS time as the time of day, UTC: "13:04:59.250" (under --hil-clock the plant's time,
// from "00:00:00.000").
std::string time_of_day_text(std::int64_t stamp_ns);
// One line per vehicle, one for the pole, then the latest events. Vehicles never heard of say so.
std::string render_status(const StatusView& view);

// The readers behind a StatusView.
class StatusWatch {
 public:
  explicit StatusWatch(const dds::Participant& participant);
  // Waits up to `timeout` for a pole telemetry sample (published with the vehicles' each period),
  // then takes everything that arrived.
  void wait_and_take(std::chrono::nanoseconds timeout);
  const StatusView& view() const { return view_; }

 private:
  void take_all();

  std::array<dds::Reader<dds::VehicleTelemetry>, 2> vehicles_;  // vehicle 1, vehicle 2
  dds::Reader<dds::PoleTelemetry> pole_;
  dds::Reader<dds::Event> events_;
  StatusView view_;
};

}  // namespace gs::service
