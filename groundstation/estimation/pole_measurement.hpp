// The pole's motion-capture measurement and the innovation statistics every pole filter reports.
//
// Measurement: the pole's centre p_p and its direction n (the body z-axis, eq. (21)). The
// direction is used through its two components in the plane normal to the predicted direction
// (tangent_basis), so a filter sees 5 independent measurements: 3 of position and 2 of direction,
// with noise sigma_p and sigma_n (1 mm / 1 mrad for a typical arena).
//
// Innovation statistics (Section IV, "the ratio of the innovation to the measurement
// covariance"): NIS = nu^T S^-1 nu (chi-square with 5 dof when the filter is consistent) and the
// Gaussian log-likelihood -1/2 (NIS + ln det S + 5 ln 2 pi), which the mode selection compares
// between the filters.
#pragma once

#include <Eigen/Dense>

namespace gs::estimation {

inline constexpr int kPoleMeasurementSize = 5;
using PoleMeasurementVector = Eigen::Matrix<double, kPoleMeasurementSize, 1>;
using PoleMeasurementMatrix = Eigen::Matrix<double, kPoleMeasurementSize, kPoleMeasurementSize>;

struct PoleMeasurement {
  Eigen::Vector3d p_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d n = Eigen::Vector3d::UnitZ();  // unit
};

struct PoleInnovation {
  bool valid = false;  // false: the filter cannot explain a pole measurement at all
  PoleMeasurementVector nu = PoleMeasurementVector::Zero();
  PoleMeasurementMatrix s = PoleMeasurementMatrix::Identity();
  double nis = 0.0;
  double log_likelihood = 0.0;
};

// NIS and log-likelihood of an innovation nu with covariance s (valid = false if s is not
// positive definite or nu is not finite).
PoleInnovation make_pole_innovation(const PoleMeasurementVector& nu, const PoleMeasurementMatrix& s);

// The measurement noise covariance: sigma_p^2 + extra_position_variance on the position,
// sigma_n^2 on the two direction components.
PoleMeasurementMatrix pole_measurement_noise(double sigma_p_m, double sigma_n_rad,
                                             double extra_position_variance_m2 = 0.0);

// A pole filter's measurement linearised at its prediction: the innovation nu, the Jacobian H
// of the measurement with respect to the filter's N states, and the noise R.
template <int N>
struct LinearisedPoleMeasurement {
  PoleMeasurementVector nu = PoleMeasurementVector::Zero();
  Eigen::Matrix<double, kPoleMeasurementSize, N> h = Eigen::Matrix<double, kPoleMeasurementSize, N>::Zero();
  PoleMeasurementMatrix r = PoleMeasurementMatrix::Identity();
};

// The innovation statistics of a linearised measurement against the state covariance P.
// The product of two small fixed-size matrices, coefficient by coefficient. Eigen sends fixed-size
// products with a dimension of 8 or more (EIGEN_CACHEFRIENDLY_PRODUCT_THRESHOLD) to its blocked
// GEMM kernel, whose packing costs more than the arithmetic at the free-flight filter's 13 x 13:
// perf put 47 % of an estimator update there.
template <class A, class B>
auto small_product(const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<B>& b) {
  return a.lazyProduct(b).eval();
}

// a p a^T.
template <class A, class P>
auto congruence(const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<P>& p) {
  return small_product(small_product(a, p), a.transpose());
}

template <int N>
PoleInnovation pole_innovation(const LinearisedPoleMeasurement<N>& m, const Eigen::Matrix<double, N, N>& p) {
  return make_pole_innovation(m.nu, congruence(m.h, p) + m.r);
}

// The same with the NIS and log-likelihood judged on H P H^T + judged_r (the motion capture's
// own noise) while s, which the gain uses, keeps the filter's m.r: a filter that trusts the poses
// less is weighed by the mode selector as any other (pole_on_vehicle_ekf.hpp).
template <int N>
PoleInnovation pole_innovation(const LinearisedPoleMeasurement<N>& m, const Eigen::Matrix<double, N, N>& p,
                               const PoleMeasurementMatrix& judged_r) {
  const PoleMeasurementMatrix hph = congruence(m.h, p);
  PoleInnovation inn = make_pole_innovation(m.nu, hph + judged_r);
  inn.s = hph + m.r;
  return inn;
}

// The Kalman correction for a valid innovation `inn` of `m`: returns the state step K nu and
// updates P in the Joseph form (kept symmetric), which stays positive definite when K is off.
// (I - K H) P (I - K H)^T is formed as A - (A H^T) K^T with A = P - K (P H^T)^T (P symmetric):
// products with the 5 measurement columns instead of two N x N x N ones, the same matrix to
// rounding.
template <int N>
Eigen::Matrix<double, N, 1> kalman_correction(const LinearisedPoleMeasurement<N>& m,
                                              const PoleInnovation& inn, Eigen::Matrix<double, N, N>& p) {
  const PoleMeasurementMatrix s_inverse = inn.s.llt().solve(PoleMeasurementMatrix::Identity());
  const Eigen::Matrix<double, N, kPoleMeasurementSize> ph = small_product(p, m.h.transpose());
  const Eigen::Matrix<double, N, kPoleMeasurementSize> k = small_product(ph, s_inverse);
  const Eigen::Matrix<double, N, N> a = p - small_product(k, ph.transpose());
  p = a - small_product(small_product(a, m.h.transpose()), k.transpose()) + congruence(k, m.r);
  p = 0.5 * (p + p.transpose()).eval();
  return k * m.nu;
}

}  // namespace gs::estimation
