// The motion-capture system: it captures the poses of both vehicles and the pole at its frame
// rate, adds noise to each (position per axis; attitude as a small rotation about a random
// body-frame axis), loses a body now and then (dropout), and delivers each frame after its
// latency (plus jitter), in capture order, as a ground station receiving it over the network
// sees it.
#pragma once

#include "hil/plant/outages.hpp"

#include <array>
#include <cstdint>
#include <deque>

#include "hil/plant/plant_config.hpp"
#include "hil/plant/random.hpp"
#include "hil/plant/types.hpp"

namespace hil {

// What the motion-capture system captured, on the plant's side (truth plus its noise, with the
// capture and delivery times); the ground station's input is gs::estimation::MocapFrame, made
// from it in hil/sil/ground_station_frame.hpp.
struct CapturedPose {
  bool seen = false;  // false: the body was not found in this frame (dropout)
  Vec3 position_m = Vec3::Zero();
  Quat attitude = Quat::Identity();  // body -> inertial; for the pole, body z is n
};

struct CapturedFrame {
  std::uint64_t index = 0;             // capture count; capture_t_s = index / rate
  double capture_t_s = 0.0;            // when the poses were true
  double delivery_t_s = 0.0;           // when the frame becomes visible
  std::array<CapturedPose, 3> pose{};  // indexed by Body
};

class MocapModel {
 public:
  MocapModel(const MocapConfig& config, std::uint64_t seed);

  // Records a frame of the true poses (indexed by Body) captured at t_s; without
  // `dropouts_active` no body is lost in it (Plant::losses_active()).
  void capture(std::uint64_t index, double t_s, const std::array<RigidBodyState, 3>& truth,
               bool dropouts_active = true);
  // The oldest frame delivered by now_s, if any.
  bool pop(double now_s, CapturedFrame& out);
  std::size_t in_flight() const { return queue_.size(); }

  // Frames older than this many are dropped when nobody reads them.
  static constexpr std::size_t kQueueLimit = 100000;

 private:
  MocapConfig config_;
  Random rng_;
  std::array<OutageSchedule, 3> outages_;  // per body, with dropout_outage_s
  std::deque<CapturedFrame> queue_;
  double last_delivery_t_s_ = -1e300;
};

}  // namespace hil
