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

const char* link_text(std::int32_t link) {
  switch (link) {
    case pa_arena_link_up: return "up";
    case pa_arena_link_lost: return "LOST";
    case pa_arena_link_unheard: break;
  }
  return "unheard";
}

std::string pole_mode_text(std::int32_t mode) {
  if (mode != pa_arena_pole_free && mode != pa_arena_pole_on_vehicle1 && mode != pa_arena_pole_on_vehicle2)
    return "mode " + std::to_string(mode);
  return std::string(
      estimation::pole_mode_name(dds::pole_mode_from_dds(static_cast<pa_arena_PoleMode>(mode))));
}

}  // namespace

std::string event_kind_name(std::int32_t kind) {
  if (kind < 0 || static_cast<std::size_t>(kind) >= std::size(kEventNames))
    return "event " + std::to_string(kind);
  return kEventNames[kind];
}

void StatusView::add(const pa_arena_VehicleTelemetry& telemetry) {
  const pa::VehicleId v(telemetry.vehicle);
  if (pa::is_act_vehicle(v)) vehicles[pa::act_slot(v)] = telemetry;
}

void StatusView::add(const pa_arena_Event& event) {
  events.push_back(EventLine{event.time_ns, dds::raw_enum(event.kind), event.vehicle, event.detail});
  while (events.size() > kEvents) events.pop_front();
}

std::string render_status(const StatusView& view) {
  std::string out;
  char line[256];
  for (const pa::VehicleId v : pa::kActVehicles) {
    const std::optional<pa_arena_VehicleTelemetry>& t = view.vehicles[pa::act_slot(v)];
    if (!t) {
      std::snprintf(line, sizeof line, "vehicle %d  no telemetry\n", int(v.node()));
      out += line;
      continue;
    }
    std::snprintf(line, sizeof line, "vehicle %d  link %-7s  task %-9s  vehicle %-16s", int(v.node()),
                  link_text(dds::raw_enum(t->link)), task_text(t->mode).c_str(),
                  vehicle_mode_text(t->vehicle_mode).c_str());
    out += line;
    if (t->estimate_valid) {
      const pa_arena_Estimate& e = t->estimate;
      std::snprintf(line, sizeof line, "  at %6.2f %6.2f %6.2f m  speed %5.2f m/s\n", e.position_m.x,
                    e.position_m.y, e.position_m.z,
                    std::sqrt(e.velocity_mps.x * e.velocity_mps.x + e.velocity_mps.y * e.velocity_mps.y +
                              e.velocity_mps.z * e.velocity_mps.z));
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
    const pa_arena_PoleTelemetry& p = *view.pole;
    std::snprintf(line, sizeof line, "pole       %-11s  centre %6.2f %6.2f %6.2f m",
                  pole_mode_text(dds::raw_enum(p.mode)).c_str(), p.estimate.position_m.x,
                  p.estimate.position_m.y, p.estimate.position_m.z);
    out += line;
    if (p.catch_predicted) {
      std::snprintf(line, sizeof line, "  catch by vehicle %d in %.2f s at %.2f %.2f %.2f m\n",
                    int(p.catch_vehicle), dds::to_seconds(p.catch_time_ns - p.time_ns), p.catch_point_m.x,
                    p.catch_point_m.y, p.catch_point_m.z);
      out += line;
    } else {
      out += "  no catch predicted\n";
    }
  }
  out += view.events.empty() ? "events     none yet\n" : "events\n";
  for (const EventLine& e : view.events) {
    std::snprintf(line, sizeof line, "  %10.3f  %-13s %-9s  ", dds::to_seconds(e.time_ns),
                  event_kind_name(e.kind).c_str(),
                  e.vehicle == 0 ? "" : ("vehicle " + std::to_string(e.vehicle)).c_str());
    out += line;
    out += e.detail;
    out += "\n";
  }
  return out;
}

StatusWatch::StatusWatch(const dds::Participant& participant)
    : vehicles_(participant), pole_(participant), events_(participant) {}

void StatusWatch::wait_and_take(std::chrono::nanoseconds timeout) {
  if (const pa_arena_VehicleTelemetry* t = vehicles_.wait_take(timeout)) view_.add(*t);
  take_all();
}

void StatusWatch::take_all() {
  while (const pa_arena_VehicleTelemetry* t = vehicles_.take()) view_.add(*t);
  while (const pa_arena_PoleTelemetry* p = pole_.take()) view_.pole = *p;
  while (const pa_arena_Event* e = events_.take()) view_.add(*e);
}

}  // namespace gs::service
