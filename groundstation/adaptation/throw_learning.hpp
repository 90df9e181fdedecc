// The throw learnt from past trials (the paper's outlook, Section VIII: "methods for improving
// the throw maneuver based on past trials"): iterative learning control on its end state.
//
// The throw is flown by the TV-LQR about the planned trajectory (throw_tracking.hpp). A plant
// that differs from the planar model in a way that repeats from throw to throw (motors weaker
// than their map, more drag than the coefficients say) leaves the same error at the launch every
// time: the feedback only reacts to it. After throw k, with the launch-state error
//     e_k = s_flown(T) - s_planned(T)        (x, z, x', z', alpha, alpha' of the Fig. 5 state)
// the next throw tracks the plan shifted by a correction c, blended in over the throw
// (planning/throw_correction.hpp: s_ref(tau) = s_planned(tau) + sigma(tau / T) c), and c moves
// against the error:
//     c_{k+1} = c_k - gain (G^T G + lambda I)^-1 G^T e_k.
// G is the sensitivity of the flown end state to c (planning::end_shift_sensitivity, carried by
// the shared Fig. 5 throw): the tracking loop follows a shifted reference only in part, and a
// shift of one component moves others (a higher velocity reference also moves the position).
// G is far from diagonal (an alpha shift moves x most) and its plain inverse has entries near
// 20, which amplify the difference between the model's G and the plant's (its rate loop,
// latencies, the drag): in the closed loop with motors 5 % weak and 30 % more drag
// (tests/hil/throw_learning_test.cpp) the plain inverse and lambda 0.01 diverged, lambda 0.1 to
// 1 oscillated, and lambda 3 brought the error down steadily, to 0.4 to 0.5 of the first throw's
// from the 8th throw on; with G the identity the position overshot (a velocity correction moved
// x as much as the x correction did). Each correction component is
// bounded, and a throw whose error exceeds a bound is not learnt from (a launch far from the plan
// is a failed or spoiled throw, not a model error that repeats).
//
// The correction is a function of the launch errors alone, so the adaptation store's history
// (each throw's launch state, throw_record.hpp) is its durable form: replaying the errors of the
// current epoch rebuilds it.
#pragma once

#include <Eigen/Core>

#include "groundstation/planning/catching_instant.hpp"

namespace gs::adaptation {

struct ThrowLearningSettings {
  double gain = 0.5;     // 0: the throw is not learnt
  double damping = 3.0;  // lambda of the damped least-squares inverse of G
  // Bounds of each component of the correction, and of an error that is learnt from.
  double max_position_m = 0.2;
  double max_speed_mps = 1.0;
  double max_angle_rad = 0.2;
  double max_rate_radps = 2.0;
};

// The six components of a launch state as a vector (x, z, x', z', alpha, alpha').
using LaunchVector = Eigen::Matrix<double, 6, 1>;
using LaunchMatrix = Eigen::Matrix<double, 6, 6>;
LaunchVector launch_vector(const planning::PlanarLaunchState& s);
planning::PlanarLaunchState launch_state(const LaunchVector& v);

struct ThrowCorrection {
  LaunchVector end_shift = LaunchVector::Zero();  // c
  int throws = 0;                                 // errors learnt from
};

// (G^T G + lambda I)^-1 G^T.
LaunchMatrix damped_inverse(const LaunchMatrix& g, double lambda);

// c_{k+1} from c_k and one throw's flown and planned launch states, with damped_inverse(G).
ThrowCorrection learn_from_throw(const ThrowCorrection& correction, const planning::PlanarLaunchState& flown,
                                 const planning::PlanarLaunchState& planned,
                                 const ThrowLearningSettings& settings,
                                 const LaunchMatrix& inverse_sensitivity);

}  // namespace gs::adaptation
