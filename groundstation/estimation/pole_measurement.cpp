#include "groundstation/estimation/pole_measurement.hpp"

#include <cmath>
#include <numbers>

namespace gs::estimation {

PoleInnovation make_pole_innovation(const PoleMeasurementVector& nu, const PoleMeasurementMatrix& s) {
  PoleInnovation out;
  out.nu = nu;
  out.s = s;
  if (!nu.allFinite() || !s.allFinite()) return out;
  const Eigen::LLT<PoleMeasurementMatrix> llt(s);
  if (llt.info() != Eigen::Success) return out;
  const PoleMeasurementVector w = llt.matrixL().solve(nu);
  double log_det = 0.0;
  for (int i = 0; i < kPoleMeasurementSize; ++i) log_det += std::log(llt.matrixL()(i, i));
  log_det *= 2.0;
  out.nis = w.squaredNorm();
  out.log_likelihood = -0.5 * (out.nis + log_det + kPoleMeasurementSize * std::log(2.0 * std::numbers::pi));
  out.valid = std::isfinite(out.log_likelihood);
  return out;
}

PoleMeasurementMatrix pole_measurement_noise(double sigma_p_m, double sigma_n_rad,
                                             double extra_position_variance_m2) {
  PoleMeasurementVector d;
  const double vp = sigma_p_m * sigma_p_m + extra_position_variance_m2;
  const double vn = sigma_n_rad * sigma_n_rad;
  d << vp, vp, vp, vn, vn;
  return d.asDiagonal();
}

}  // namespace gs::estimation
