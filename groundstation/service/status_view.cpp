#include "groundstation/service/status_view.hpp"

#include <cmath>
#include <cstdio>
#include <iterator>

#include "groundstation/dds/mocap_conversion.hpp"
#include "groundstation/dds/telemetry_conversion.hpp"
#include "groundstation/estimation/pole_mode.hpp"
#include "groundstation/mission/vehicle_sequencer.hpp"
#include "pa/protocol.hpp"
#include "pa/vehicle_id.hpp"

namespace gs::service {
namespace {

constexpr const char* kEventNames[] = {"launch",   "impact",       "catch success", "catch miss",  "abort",
                                       "failsafe", "vehicle lost", "vehicle back",  "task change", "refused",
                                       "accepted", "attempt",      "pole wanted"};

std::string task_text(std::uint8_t task) {
  if (task >= mission::kTaskCount) return "task " + std::to_string(task);
  return std::string(mission::task_name(static_cast<mission::Task>(task)));
}

std::string vehicle_mode_text(std::uint8_t mode) {
  if (mode > pa::proto::kModeMax) return "mode " + std::to_string(mode);
  return pa::proto::mode_name(static_cast<pa::proto::Mode>(mode));
}

const char* link_text(std::uint8_t link) {
  switch (link) {
    case dds::link_state::kUp: return "up";
    case dds::link_state::kLost: return "LOST";
    case dds::link_state::kUnheard: return "unheard";
    default: return "unknown";
  }
}

std::string pole_mode_text(std::uint8_t mode) {
  const std::optional<estimation::PoleMode> m = dds::pole_mode_from_ros(mode);
  return m ? std::string(estimation::pole_mode_name(*m)) : "mode " + std::to_string(mode);
}

}  // namespace

std::string event_kind_name(std::uint8_t kind) {
  static_assert(std::size(kEventNames) == dds::event_kind::kLast + 1);
  if (!dds::is_event_kind(kind)) return "event " + std::to_string(kind);
  return kEventNames[kind];
}

std::string time_of_day_text(std::int64_t stamp_ns) {
  constexpr std::int64_t kDay_ms = 86'400'000;
  const std::int64_t ms = ((stamp_ns / 1'000'000) % kDay_ms + kDay_ms) % kDay_ms;
  char text[16];
  std::snprintf(text, sizeof text, "%02d:%02d:%02d.%03d", int(ms / 3'600'000), int(ms / 60'000 % 60),
                int(ms / 1000 % 60), int(ms % 1000));
  return text;
}

void StatusView::add(const dds::VehicleTelemetry& telemetry) {
  const pa::VehicleId v(telemetry.vehicle);
  if (pa::is_act_vehicle(v)) vehicles[pa::act_slot(v)] = telemetry;
}

void StatusView::add(const dds::Event& event) {
  events.push_back(EventLine{dds::stamp_nanoseconds(event.stamp), event.kind, event.vehicle, event.detail});
  while (events.size() > kEvents) events.pop_front();
}

std::string render_status(const StatusView& view) {
  std::string out;
  char line[256];
  for (const pa::VehicleId v : pa::kActVehicles) {
    const std::optional<dds::VehicleTelemetry>& t = view.vehicles[pa::act_slot(v)];
    if (!t) {
      std::snprintf(line, sizeof line, "vehicle %d  no telemetry\n", int(v.node()));
      out += line;
      continue;
    }
    std::snprintf(line, sizeof line, "vehicle %d  link %-7s  task %-9s  vehicle %-16s", int(v.node()),
                  link_text(t->link), task_text(t->task).c_str(), vehicle_mode_text(t->vehicle_mode).c_str());
    out += line;
    if (t->estimate_valid) {
      const auto& p = t->position;
      const auto& v = t->velocity;
      std::snprintf(line, sizeof line, "  at %6.2f %6.2f %6.2f m  speed %5.2f m/s\n", p.x, p.y, p.z,
                    std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z));
      out += line;
    } else {
      out += "  no estimate\n";
    }
  }
  if (!view.pole) {
    out += "pole       no telemetry\n";
  } else if (!view.pole->estimate_valid) {
    out += "pole       not seen\n";
  } else {
    const dds::PoleTelemetry& p = *view.pole;
    std::snprintf(line, sizeof line, "pole       %-11s  centre %6.2f %6.2f %6.2f m",
                  pole_mode_text(p.mode).c_str(), p.position.x, p.position.y, p.position.z);
    out += line;
    if (p.catch_predicted) {
      std::snprintf(line, sizeof line, "  catch by vehicle %d in %.2f s at %.2f %.2f %.2f m\n",
                    int(p.catch_vehicle),
                    dds::to_seconds(dds::stamp_nanoseconds(p.catch_stamp) - dds::stamp_nanoseconds(p.stamp)),
                    p.catch_point.x, p.catch_point.y, p.catch_point.z);
      out += line;
    } else {
      out += "  no catch predicted\n";
    }
  }
  out += view.events.empty() ? "events     none yet\n" : "events\n";
  for (const EventLine& e : view.events) {
    std::snprintf(line, sizeof line, "  %s  %-13s %-9s  ", time_of_day_text(e.stamp_ns).c_str(),
                  event_kind_name(e.kind).c_str(),
                  e.vehicle == 0 ? "" : ("vehicle " + std::to_string(e.vehicle)).c_str());
    out += line;
    out += e.detail;
    out += "\n";
  }
  return out;
}

StatusWatch::StatusWatch(const dds::Participant& participant)
    : vehicles_{dds::Reader<dds::VehicleTelemetry>(participant,
                                                   dds::vehicle_telemetry_topic(pa::kVehicle1).c_str()),
                dds::Reader<dds::VehicleTelemetry>(participant,
                                                   dds::vehicle_telemetry_topic(pa::kVehicle2).c_str())},
      pole_(participant),
      events_(participant) {}

void StatusWatch::wait_and_take(std::chrono::nanoseconds timeout) {
  if (const dds::PoleTelemetry* p = pole_.wait_take(timeout)) view_.pole = *p;
  take_all();
}

void StatusWatch::take_all() {
  for (dds::Reader<dds::VehicleTelemetry>& vehicle : vehicles_) {
    while (const dds::VehicleTelemetry* t = vehicle.take()) view_.add(*t);
  }
  while (const dds::PoleTelemetry* p = pole_.take()) view_.pole = *p;
  while (const dds::Event* e = events_.take()) view_.add(*e);
}

}  // namespace gs::service
