#include "groundstation/control/hover_lqr.hpp"

namespace gs::control {

LinearSystem hover_linearisation(double gravity_mps2) {
  using namespace hover;
  LinearSystem sys{Eigen::MatrixXd::Zero(kStateSize, kStateSize),
                   Eigen::MatrixXd::Zero(kStateSize, kInputSize)};
  sys.A(kX, kVx) = sys.A(kY, kVy) = sys.A(kZ, kVz) = 1.0;
  sys.A(kVx, kPitch) = gravity_mps2;
  sys.A(kVy, kRoll) = -gravity_mps2;
  sys.B(kVz, kThrust) = 1.0;
  sys.B(kRoll, kRateX) = sys.B(kPitch, kRateY) = sys.B(kYaw, kRateZ) = 1.0;
  return sys;
}

LqrWeights hover_lqr_weights() {
  LqrWeights w;
  w.state = (Eigen::VectorXd(hover::kStateSize) << 4, 4, 4, 1, 1, 1, 0.5, 0.5, 0.5).finished();
  w.input = (Eigen::VectorXd(hover::kInputSize) << 0.5, 0.2, 0.2, 0.2).finished();
  return w;
}

LqrWeights catch_lqr_weights() {
  LqrWeights w = hover_lqr_weights();
  w.state(hover::kX) *= 4.0;
  w.state(hover::kY) *= 4.0;
  return w;
}

LqrGain hover_lqr(const LqrWeights& weights, double gravity_mps2) {
  return solve_lqr(hover_linearisation(gravity_mps2), weights);
}

}  // namespace gs::control
