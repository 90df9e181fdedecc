#include "groundstation/control/tvlqr.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

namespace gs::control {

LinearisationFn interpolate_linearisation(std::vector<double> times_s, std::vector<LinearSystem> samples) {
  if (times_s.empty() || times_s.size() != samples.size()) return {};
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (samples[i].A.rows() != samples[0].A.rows() || samples[i].A.cols() != samples[0].A.cols() ||
        samples[i].B.rows() != samples[0].B.rows() || samples[i].B.cols() != samples[0].B.cols() ||
        !std::isfinite(times_s[i]) || (i > 0 && !(times_s[i] > times_s[i - 1]))) {
      return {};
    }
  }
  return [times = std::move(times_s), sys = std::move(samples)](double t_s) -> LinearSystem {
    if (t_s <= times.front()) return sys.front();
    if (t_s >= times.back()) return sys.back();
    const std::size_t i =
        static_cast<std::size_t>(std::upper_bound(times.begin(), times.end(), t_s) - times.begin()) - 1;
    const double w = (t_s - times[i]) / (times[i + 1] - times[i]);
    return LinearSystem{(1.0 - w) * sys[i].A + w * sys[i + 1].A, (1.0 - w) * sys[i].B + w * sys[i + 1].B};
  };
}

TvLqrGains::TvLqrGains(std::vector<double> times_s, std::vector<Eigen::MatrixXd> gains,
                       std::vector<Eigen::MatrixXd> costs)
    : times_s_(std::move(times_s)), gains_(std::move(gains)), costs_(std::move(costs)) {}

Eigen::MatrixXd TvLqrGains::interpolate(const std::vector<Eigen::MatrixXd>& values, double t_s) const {
  if (values.empty()) return {};
  if (!(t_s > times_s_.front())) return values.front();  // also NaN
  if (t_s >= times_s_.back()) return values.back();
  const std::size_t i =
      static_cast<std::size_t>(std::upper_bound(times_s_.begin(), times_s_.end(), t_s) - times_s_.begin()) -
      1;
  const double w = (t_s - times_s_[i]) / (times_s_[i + 1] - times_s_[i]);
  return (1.0 - w) * values[i] + w * values[i + 1];
}

Eigen::MatrixXd TvLqrGains::gain(double t_s) const { return interpolate(gains_, t_s); }
Eigen::MatrixXd TvLqrGains::cost(double t_s) const { return interpolate(costs_, t_s); }

TvLqrGains solve_tv_lqr(const LinearisationFn& linearisation, const Eigen::MatrixXd& Q,
                        const Eigen::MatrixXd& R, const Eigen::MatrixXd& Q_final, double t0_s, double tf_s,
                        const TvLqrOptions& options) {
  const Eigen::Index n = Q.rows();
  const Eigen::Index m = R.rows();
  if (!linearisation || Q.cols() != n || R.cols() != m || Q_final.rows() != n || Q_final.cols() != n ||
      !Q.allFinite() || !R.allFinite() || !Q_final.allFinite() || !std::isfinite(t0_s) ||
      !std::isfinite(tf_s) || !(tf_s > t0_s) || !(options.grid_step_s > 0.0) || !(options.max_step_s > 0.0)) {
    return {};
  }
  Eigen::LLT<Eigen::MatrixXd> r_llt(R);
  if (r_llt.info() != Eigen::Success) return {};

  // Grid t0 .. tf; the last interval may be shorter.
  const auto intervals = static_cast<std::size_t>(std::ceil((tf_s - t0_s) / options.grid_step_s - 1e-9));
  std::vector<double> times(intervals + 1);
  for (std::size_t k = 0; k <= intervals; ++k) {
    times[k] = std::min(t0_s + static_cast<double>(k) * options.grid_step_s, tf_s);
  }
  times.back() = tf_s;

  // dP/ds with s = tf - t (backward time): A^T P + P A - P S P + Q.
  auto rhs = [&](double t, const Eigen::MatrixXd& P, bool& ok) -> Eigen::MatrixXd {
    const LinearSystem sys = linearisation(t);
    if (sys.A.rows() != n || sys.A.cols() != n || sys.B.rows() != n || sys.B.cols() != m) {
      ok = false;
      return P;
    }
    const Eigen::MatrixXd PB = P * sys.B;
    return sys.A.transpose() * P + P * sys.A - PB * r_llt.solve(PB.transpose()) + Q;
  };
  auto gain_at = [&](double t, const Eigen::MatrixXd& P, bool& ok) -> Eigen::MatrixXd {
    const LinearSystem sys = linearisation(t);
    if (sys.B.rows() != n || sys.B.cols() != m) {
      ok = false;
      return {};
    }
    return r_llt.solve(sys.B.transpose() * P);
  };

  std::vector<Eigen::MatrixXd> costs(times.size()), gains(times.size());
  Eigen::MatrixXd P = 0.5 * (Q_final + Q_final.transpose());
  bool ok = true;
  costs.back() = P;
  gains.back() = gain_at(tf_s, P, ok);
  if (!ok) return {};
  for (std::size_t k = intervals; k-- > 0;) {
    const double span = times[k + 1] - times[k];
    const int steps = std::max(1, static_cast<int>(std::ceil(span / options.max_step_s - 1e-9)));
    const double h = span / steps;
    double t = times[k + 1];
    for (int i = 0; i < steps; ++i) {
      // Backward in t: each stage at t - c h.
      const Eigen::MatrixXd k1 = rhs(t, P, ok);
      const Eigen::MatrixXd k2 = rhs(t - 0.5 * h, P + 0.5 * h * k1, ok);
      const Eigen::MatrixXd k3 = rhs(t - 0.5 * h, P + 0.5 * h * k2, ok);
      const Eigen::MatrixXd k4 = rhs(t - h, P + h * k3, ok);
      P += (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
      P = 0.5 * (P + P.transpose()).eval();
      t -= h;
    }
    if (!ok || !P.allFinite()) return {};
    costs[k] = P;
    gains[k] = gain_at(times[k], P, ok);
    if (!ok) return {};
  }
  return TvLqrGains(std::move(times), std::move(gains), std::move(costs));
}

}  // namespace gs::control
