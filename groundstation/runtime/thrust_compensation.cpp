#include "groundstation/runtime/thrust_compensation.hpp"

#include <algorithm>

namespace gs::runtime {

ThrustGainSample thrust_gain_sample(mission::Task task, double height_m, double min_height_m,
                                    double pole_weight_mps2) {
  using mission::Task;
  const bool steady = task == Task::take_off || task == Task::hover || task == Task::wait ||
                      task == Task::retreat || task == Task::clear || task == Task::balance;
  return {steady && height_m > min_height_m, task == Task::balance ? pole_weight_mps2 : 0.0};
}

void measure_thrust_gain(estimation::ThrustGainEstimator& gain, mission::Task task, double t_s,
                         const estimation::MocapPose& pose, double min_height_m, double pole_weight_mps2) {
  const ThrustGainSample sample = thrust_gain_sample(task, pose.p_m.z(), min_height_m, pole_weight_mps2);
  gain.pose(t_s, pose.p_m.z(), (pose.q * Eigen::Vector3d::UnitZ()).z(), sample.load_mps2, sample.steady);
}

double compensated_thrust_mps2(double a_q_mps2, double gain, const model::VehicleLimits& limits,
                               double thrust_max_mps2) {
  if (a_q_mps2 <= 0.0) return a_q_mps2;
  return std::clamp(std::clamp(a_q_mps2, limits.a_q_min_mps2, limits.a_q_max_mps2) / gain,
                    limits.a_q_min_mps2, thrust_max_mps2);
}

}  // namespace gs::runtime
