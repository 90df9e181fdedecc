#include "hil/plant/mocap.hpp"

#include <algorithm>

namespace hil {

MocapModel::MocapModel(const MocapConfig& config, std::uint64_t seed)
    : config_(config),
      rng_(seed, RandomStream::mocap),
      outages_{{OutageSchedule(config.dropout_probability, config.dropout_outage_s),
                OutageSchedule(config.dropout_probability, config.dropout_outage_s),
                OutageSchedule(config.dropout_probability, config.dropout_outage_s)}} {}

void MocapModel::capture(std::uint64_t index, double t_s, const std::array<RigidBodyState, 3>& truth,
                         bool dropouts_active) {
  CapturedFrame frame;
  frame.index = index;
  frame.capture_t_s = t_s;
  // The draw order is fixed (per body: dropout, position, attitude) so frames are reproducible.
  for (std::size_t b = 0; b < truth.size(); ++b) {
    CapturedPose& pose = frame.pose[b];
    const double draw = rng_.uniform();
    const bool lost = dropouts_active &&
                      (config_.dropout_outage_s > 0.0 ? outages_[b].out(t_s, [&] { return rng_.uniform(); })
                                                      : draw < config_.dropout_probability);
    Vec3 dp;
    Vec3 dtheta;
    for (int i = 0; i < 3; ++i) dp[i] = rng_.gaussian(config_.position_noise_m);
    for (int i = 0; i < 3; ++i) dtheta[i] = rng_.gaussian(config_.attitude_noise_rad);
    if (lost) continue;
    pose.seen = true;
    pose.position_m = truth[b].position_m + dp;
    const double angle = dtheta.norm();
    const Quat error = angle > 0.0 ? Quat(Eigen::AngleAxisd(angle, dtheta / angle)) : Quat::Identity();
    pose.attitude = (truth[b].attitude * error).normalized();
  }
  const double jitter_s = config_.jitter_s * rng_.uniform();
  frame.delivery_t_s = std::max(last_delivery_t_s_, t_s + config_.latency_s + jitter_s);
  last_delivery_t_s_ = frame.delivery_t_s;
  queue_.push_back(frame);
  if (queue_.size() > kQueueLimit) queue_.pop_front();
}

bool MocapModel::pop(double now_s, CapturedFrame& out) {
  // A tolerance well below any frame period absorbs the rounding of times built from ticks.
  if (queue_.empty() || queue_.front().delivery_t_s > now_s + 1e-9) return false;
  out = queue_.front();
  queue_.pop_front();
  return true;
}

}  // namespace hil
