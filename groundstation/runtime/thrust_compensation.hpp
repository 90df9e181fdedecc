// The measured thrust gain's part in a vehicle's setpoints (estimation/thrust_gain.hpp): when a
// pose measures the gain (the vehicle flying on its thrust alone) and with what known extra load,
// and the collective thrust a setpoint carries so that the vehicle, delivering k a_q, flies what
// the law asked for. Pure functions (thrust_compensation_test.cpp).
#pragma once

#include "groundstation/estimation/mocap_pose.hpp"
#include "groundstation/estimation/thrust_gain.hpp"
#include "groundstation/mission/vehicle_sequencer.hpp"
#include "groundstation/model/vehicle_limits.hpp"

namespace gs::runtime {

struct ThrustGainSample {
  bool steady = false;     // the pose measures the gain
  double load_mps2 = 0.0;  // the known extra load (the balanced pole's weight)
};

// Not on the floor (below `min_height_m`), not throwing, releasing, catching or with a pole
// swinging up; balancing, the pole's weight is the known extra load.
ThrustGainSample thrust_gain_sample(mission::Task task, double height_m, double min_height_m,
                                    double pole_weight_mps2);

// One pose of a vehicle flying `task`, stamped `t_s`, to its thrust-gain estimator: with its body's
// vertical and, when thrust_gain_sample says it measures the gain, the known load. Poses are
// stamped with the ground clock on arrival, the clock the commands are stamped with: the motion
// capture's own may be another (a plant slower than real time, an arena's system), and its latency
// only shifts the window by tens of milliseconds of steady flight.
void measure_thrust_gain(estimation::ThrustGainEstimator& gain, mission::Task task, double t_s,
                         const estimation::MocapPose& pose, double min_height_m, double pole_weight_mps2);

// The setpoint's thrust for `a_q_mps2` on a vehicle with thrust gain `gain`: the laws ask within
// a_q's limits of the vehicle as built, the setpoint a_q / k asks its motors for it up to their
// full thrust `thrust_max_mps2` (GroundStationConfig::airframe_thrust_max_mps2); zero stays zero
// (ARM wants a zero-thrust setpoint).
double compensated_thrust_mps2(double a_q_mps2, double gain, const model::VehicleLimits& limits,
                               double thrust_max_mps2);

}  // namespace gs::runtime
