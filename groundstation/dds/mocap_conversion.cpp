#include "groundstation/dds/mocap_conversion.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <optional>

namespace gs::dds {
namespace {

// A unit quaternion off by more than this is not a rotation the motion capture meant (float
// rounding on its way is some 1e-7).
constexpr double kUnitTolerance = 1e-3;

bool finite(const geometry_msgs_msg_dds__Point_& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

// The pose, renormalised; none when it is no pose the estimator may take.
std::optional<estimation::MocapPose> pose_from_dds(const geometry_msgs_msg_dds__Pose_& pose) {
  const auto& p = pose.position;
  const auto& q = pose.orientation;
  if (!finite(p) || !std::isfinite(q.w) || !std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z))
    return std::nullopt;
  const double norm = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  if (std::abs(norm - 1.0) > kUnitTolerance) return std::nullopt;
  estimation::MocapPose out;
  out.p_m = Eigen::Vector3d(p.x, p.y, p.z);
  out.q = Eigen::Quaterniond(q.w / norm, q.x / norm, q.y / norm, q.z / norm);
  return out;
}

// The name, or none when it is null or longer than kMaxBodyName (never read past that).
std::optional<std::string_view> bounded_name(const char* name) {
  if (name == nullptr) return std::nullopt;
  const std::size_t n = strnlen(name, kMaxBodyName + 1);
  if (n > kMaxBodyName) return std::nullopt;
  return std::string_view(name, n);
}

}  // namespace

std::string_view MocapBodyNames::vehicle(pa::VehicleId id) const {
  if (id == pa::kVehicle1) return vehicle1;
  if (id == pa::kVehicle2) return vehicle2;
  return {};
}

std::string check_body_names(const MocapBodyNames& names) {
  const std::string* all[] = {&names.vehicle1, &names.vehicle2, &names.pole};
  for (const std::string* name : all) {
    if (name->empty()) return "a motion-capture body name is empty";
    if (name->size() > kMaxBodyName)
      return "the motion-capture body name '" + *name + "' is longer than " + std::to_string(kMaxBodyName) +
             " characters";
  }
  if (names.vehicle1 == names.vehicle2 || names.vehicle1 == names.pole || names.vehicle2 == names.pole)
    return "the motion-capture body names of vehicle 1, vehicle 2 and the pole must differ (" +
           names.vehicle1 + ", " + names.vehicle2 + ", " + names.pole + ")";
  return {};
}

std::int64_t to_nanoseconds(double t_s) { return std::llround(t_s * 1e9); }
double to_seconds(std::int64_t t_ns) { return static_cast<double>(t_ns) * 1e-9; }

std::int64_t stamp_nanoseconds(const RosTime& stamp) {
  return static_cast<std::int64_t>(stamp.sec) * 1'000'000'000 + static_cast<std::int64_t>(stamp.nanosec);
}

RosTime ros_time(std::int64_t t_ns) {
  // Floor division: a time before the epoch has a negative sec and a nanosec in [0, 1e9).
  std::int64_t sec = t_ns / 1'000'000'000;
  std::int64_t nsec = t_ns % 1'000'000'000;
  if (nsec < 0) {
    nsec += 1'000'000'000;
    --sec;
  }
  return RosTime{static_cast<std::int32_t>(sec), static_cast<std::uint32_t>(nsec)};
}

MocapFrameIn mocap_frame_from_dds(const NamedPoseArray& message, const MocapBodyNames& names) {
  MocapFrameIn in;
  in.stamp_ns = stamp_nanoseconds(message.header.stamp);
  in.frame.t_s = to_seconds(in.stamp_ns);
  const std::uint32_t length = message.poses._buffer == nullptr ? 0 : message.poses._length;
  const std::uint32_t count = std::min<std::uint32_t>(length, kMaxPoses);
  in.excess_poses = length - count;
  // A name met before in this frame, whether its pose was valid or not: two bodies of one name
  // are ambiguous, and the second never stands in for a first that was invalid.
  std::array<bool, 3> seen{};  // vehicle 1, vehicle 2, pole
  for (std::uint32_t i = 0; i < count; ++i) {
    const NamedPose& body = message.poses._buffer[i];
    const std::optional<std::string_view> name = bounded_name(body.name);
    std::optional<estimation::MocapPose>* slot = nullptr;
    std::size_t index = 0;
    if (name) {
      if (*name == names.pole) {
        slot = &in.frame.pole;
        index = 2;
      } else {
        for (const pa::VehicleId vehicle : pa::kActVehicles) {
          if (*name != names.vehicle(vehicle)) continue;
          index = pa::act_slot(vehicle);
          slot = &in.frame.vehicle[index];
        }
      }
    }
    if (slot == nullptr) {
      if (in.unknown_bodies++ == 0 && name) in.first_unknown = *name;
      continue;
    }
    if (seen[index]) {
      ++in.duplicate_bodies;
      continue;
    }
    seen[index] = true;
    *slot = pose_from_dds(body.pose);
    if (!*slot) ++in.invalid_poses;
  }
  return in;
}

MocapMessage::MocapMessage() {
  std::memcpy(frame_id_.data(), kWorldFrame.data(), kWorldFrame.size());
  message_.header.frame_id = frame_id_.data();
  for (std::size_t i = 0; i < kCapacity; ++i) poses_[i].name = names_[i].data();
  message_.poses._buffer = poses_.data();
  message_.poses._maximum = static_cast<std::uint32_t>(poses_.size());
  message_.poses._release = false;  // the buffer is ours, not Cyclone's to free
}

void MocapMessage::clear(std::int64_t stamp_ns) {
  message_.header.stamp = ros_time(stamp_ns);
  message_.poses._length = 0;
}

bool MocapMessage::add(std::string_view name, const estimation::MocapPose& pose) {
  const std::size_t i = message_.poses._length;
  if (i >= kCapacity) return false;
  const std::size_t n = std::min(name.size(), kMaxBodyName);
  std::memcpy(names_[i].data(), name.data(), n);
  names_[i][n] = '\0';
  NamedPose& body = poses_[i];
  body.name = names_[i].data();
  body.pose.position = {pose.p_m.x(), pose.p_m.y(), pose.p_m.z()};
  body.pose.orientation = {pose.q.x(), pose.q.y(), pose.q.z(), pose.q.w()};
  ++message_.poses._length;
  return true;
}

void mocap_frame_to_dds(const estimation::MocapFrame& frame, std::int64_t stamp_ns,
                        const MocapBodyNames& names, MocapMessage& out) {
  out.clear(stamp_ns);
  for (const pa::VehicleId vehicle : pa::kActVehicles) {
    const auto& pose = frame.vehicle[pa::act_slot(vehicle)];
    if (pose) out.add(names.vehicle(vehicle), *pose);
  }
  if (frame.pole) out.add(names.pole, *frame.pole);
}

}  // namespace gs::dds
