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

std::string task_change_detail(mission::Task from, mission::Task to, mission::Reason reason) {
  return std::string(mission::task_name(from)) + std::string(kArrow) + std::string(mission::task_name(to)) +
         " (" + std::string(mission::reason_name(reason)) + ")";
}

std::optional<mission::Task> task_change_to(const std::string& detail) {
  const std::size_t arrow = detail.find(kArrow);
  if (arrow == std::string::npos) return std::nullopt;
  const std::size_t begin = arrow + kArrow.size();
  const std::string name = detail.substr(begin, detail.find(" (", begin) - begin);
  for (int t = 0; t < mission::kTaskCount; ++t) {
    const auto task = static_cast<mission::Task>(t);
    if (mission::task_name(task) == name) return task;
  }
  return std::nullopt;
}

}  // namespace gs::dds
