#include "groundstation/dds/event_detail.hpp"

#include <cstdio>

namespace gs::dds {

namespace {

constexpr std::string_view kArrow = " -> ";

}  // namespace

std::string attempt_event_detail(int number, const Eigen::Vector3d& origin_m) {
  char text[96];
  std::snprintf(text, sizeof text, "attempt %d, pole at %.3f %.3f %.3f", number, origin_m.x(), origin_m.y(),
                origin_m.z());
  return text;
}

std::optional<Eigen::Vector3d> attempt_event_origin(const std::string& detail) {
  Eigen::Vector3d origin;
  int number = 0;
  if (std::sscanf(detail.c_str(), "attempt %d, pole at %lf %lf %lf", &number, &origin.x(), &origin.y(),
                  &origin.z()) != 4)
    return std::nullopt;
  return origin;
}

std::string pole_wanted_detail(bool waiting) { return waiting ? "waiting" : "not waiting"; }

std::optional<bool> pole_wanted(const std::string& detail) {
  if (detail == pole_wanted_detail(true)) return true;
  if (detail == pole_wanted_detail(false)) return false;
  return std::nullopt;
}

std::string task_change_detail(mission::Task from, mission::Task to, mission::Reason reason,
                               const std::string& why) {
  return std::string(mission::task_name(from)) + std::string(kArrow) + std::string(mission::task_name(to)) +
         " (" + std::string(mission::reason_name(reason)) + ")" + (why.empty() ? "" : ": " + why);
}

}  // namespace gs::dds
