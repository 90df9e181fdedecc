#include "groundstation/dds/mocap_conversion.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace gs::dds {
namespace {

estimation::MocapPose pose_from_dds(const pa_arena_RigidBody& body) {
  estimation::MocapPose pose;
  pose.p_m = Eigen::Vector3d(body.position_m.x, body.position_m.y, body.position_m.z);
  pose.q = Eigen::Quaterniond(body.attitude.w, body.attitude.x, body.attitude.y, body.attitude.z);
  return pose;
}

// Keeps the first pose of a body; counts the others.
void place(std::optional<estimation::MocapPose>& slot, const pa_arena_RigidBody& body, MocapFrameIn& in) {
  if (slot) {
    ++in.duplicate_bodies;
    return;
  }
  slot = pose_from_dds(body);
}

}  // namespace

std::string_view vehicle_body_name(pa::VehicleId vehicle) {
  if (vehicle == pa::kVehicle1) return "vehicle1";
  if (vehicle == pa::kVehicle2) return "vehicle2";
  return {};
}

std::int64_t to_nanoseconds(double t_s) { return std::llround(t_s * 1e9); }
double to_seconds(std::int64_t t_ns) { return static_cast<double>(t_ns) * 1e-9; }

MocapFrameIn mocap_frame_from_dds(const pa_arena_MocapFrame& message) {
  MocapFrameIn in;
  in.frame.t_s = to_seconds(message.capture_time_ns);
  for (std::uint32_t i = 0; i < message.bodies._length; ++i) {
    const pa_arena_RigidBody& body = message.bodies._buffer[i];
    // A name fills its array when it is as long as the bound: never read past it.
    const std::string_view name(body.name, strnlen(body.name, sizeof body.name));
    std::optional<estimation::MocapPose>* slot = nullptr;
    if (name == kPoleBody) {
      slot = &in.frame.pole;
    } else {
      for (const pa::VehicleId vehicle : pa::kActVehicles) {
        if (name == vehicle_body_name(vehicle)) slot = &in.frame.vehicle[pa::act_slot(vehicle)];
      }
    }
    if (slot == nullptr) {
      ++in.unknown_bodies;
    } else if (body.tracked) {
      place(*slot, body, in);
    }
  }
  return in;
}

MocapMessage::MocapMessage() {
  message_.bodies._buffer = bodies_.data();
  message_.bodies._maximum = static_cast<std::uint32_t>(bodies_.size());
  message_.bodies._release = false;  // the buffer is ours, not Cyclone's to free
}

void MocapMessage::clear(std::uint64_t frame_number, std::int64_t capture_time_ns) {
  message_.frame_number = frame_number;
  message_.capture_time_ns = capture_time_ns;
  message_.bodies._length = 0;
}

bool MocapMessage::add(std::string_view name, const estimation::MocapPose& pose, bool tracked) {
  if (message_.bodies._length >= bodies_.size()) return false;
  pa_arena_RigidBody& body = bodies_[message_.bodies._length++];
  const std::size_t n = std::min(name.size(), sizeof body.name - 1);
  std::memcpy(body.name, name.data(), n);
  body.name[n] = '\0';
  body.position_m = {pose.p_m.x(), pose.p_m.y(), pose.p_m.z()};
  body.attitude = {pose.q.w(), pose.q.x(), pose.q.y(), pose.q.z()};
  body.tracked = tracked;
  return true;
}

void mocap_frame_to_dds(const estimation::MocapFrame& frame, std::uint64_t frame_number, MocapMessage& out) {
  out.clear(frame_number, to_nanoseconds(frame.t_s));
  const estimation::MocapPose untracked;
  for (const pa::VehicleId vehicle : pa::kActVehicles) {
    const auto& pose = frame.vehicle[pa::act_slot(vehicle)];
    out.add(vehicle_body_name(vehicle), pose ? *pose : untracked, pose.has_value());
  }
  out.add(kPoleBody, frame.pole ? *frame.pole : untracked, frame.pole.has_value());
}

}  // namespace gs::dds
