#include "groundstation/estimation/pole_free_flight_ekf.hpp"

#include <algorithm>
#include <cmath>

#include "groundstation/estimation/mocap_pose.hpp"

namespace gs::estimation {
namespace {

using StateVector = Eigen::Matrix<double, PoleFreeFlightEkf::kSize, 1>;
using PoleIndex = PoleFreeFlightEkf::Index;

constexpr double kMaxDragScale = 5.0;

// Linear and angular drag accelerations (16), (19) for the nominal coefficients.
void drag_accelerations(const model::PoleState& s, const model::PoleParams& nominal, double inertia_kgm2,
                        Eigen::Vector3d& linear, Eigen::Vector3d& angular) {
  const model::PoleDrag d = model::pole_drag(s, nominal);
  linear = (d.axial_force_N + d.normal_force_N) / nominal.mass_kg;
  angular = d.torque_Nm / inertia_kgm2;
}

// The covariance through the normalisation x -> (p, v, n/|n|, Omega - (Omega.n) n, k) at a
// normalised state: P <- T P T^T with T the identity except in the (n, Omega) rows, where it
// removes the radial part of n and the axial part of Omega. Only those rows and columns change,
// so T is applied as its 6 x 6 block.
void normalise_covariance(const model::PoleState& s, PoleFreeFlightEkf::StateCovariance& p) {
  static_assert(PoleIndex::kW == PoleIndex::kN + 3);
  const Eigen::Matrix3d proj = Eigen::Matrix3d::Identity() - s.n * s.n.transpose();
  Eigen::Matrix<double, 6, 6> t = Eigen::Matrix<double, 6, 6>::Zero();
  t.block<3, 3>(0, 0) = proj;
  t.block<3, 3>(3, 3) = proj;
  t.block<3, 3>(3, 0) = -s.n * s.omega_radps.transpose();
  const Eigen::Matrix<double, 6, PoleFreeFlightEkf::kSize> rows =
      small_product(t, p.middleRows<6>(PoleIndex::kN));
  p.middleRows<6>(PoleIndex::kN) = rows;
  const Eigen::Matrix<double, PoleFreeFlightEkf::kSize, 6> cols =
      small_product(p.middleCols<6>(PoleIndex::kN), t.transpose());
  p.middleCols<6>(PoleIndex::kN) = cols;
}

}  // namespace

PoleFreeFlightEkf::PoleFreeFlightEkf(const PoleFreeFlightEkfParams& params) : params_(params) {}

model::PoleParams PoleFreeFlightEkf::scaled_model() const {
  model::PoleParams m = params_.pole;
  m.drag_axial *= drag_scale_;
  m.drag_normal *= drag_scale_;
  m.drag_rotational *= drag_scale_;
  return m;
}

void PoleFreeFlightEkf::reset(const model::PoleState& state, const PoleCovariance& covariance,
                              double drag_scale, double drag_scale_sigma) {
  state_ = model::normalised_pole_state(state);
  drag_scale_ = std::clamp(drag_scale, 0.0, kMaxDragScale);
  p_.setZero();
  p_.topLeftCorner<12, 12>() = 0.5 * (covariance + covariance.transpose());
  p_(kK, kK) = params_.estimate_drag_scale ? drag_scale_sigma * drag_scale_sigma : 0.0;
  normalise_covariance(state_, p_);
  last_nis_ = 0.0;
}

PoleFreeFlightEkf::StateCovariance PoleFreeFlightEkf::jacobian() const {
  StateCovariance f = StateCovariance::Zero();
  f.block<3, 3>(kP, kV).setIdentity();
  f.block<3, 3>(kN, kN) = cross_matrix(state_.omega_radps);  // d(Omega x n)/dn, (22)
  f.block<3, 3>(kN, kW) = -cross_matrix(state_.n);           // d(Omega x n)/dOmega

  const double inertia = model::pole_inertia_kgm2(params_.pole);
  Eigen::Vector3d lin0;
  Eigen::Vector3d ang0;
  drag_accelerations(state_, params_.pole, inertia, lin0, ang0);
  // Columns of v (3..5), n (6..8) and Omega (9..11) by forward differences.
  for (int j = 0; j < 9; ++j) {
    model::PoleState s = state_;
    Eigen::Vector3d* block = j < 3 ? &s.v_mps : (j < 6 ? &s.n : &s.omega_radps);
    const int c = j % 3;
    const double eps = 1e-6 * std::max(1.0, std::abs((*block)(c)));
    (*block)(c) += eps;
    Eigen::Vector3d lin;
    Eigen::Vector3d ang;
    drag_accelerations(s, params_.pole, inertia, lin, ang);
    f.block<3, 1>(kV, kV + j) = drag_scale_ * (lin - lin0) / eps;  // (16)
    f.block<3, 1>(kW, kV + j) = drag_scale_ * (ang - ang0) / eps;  // (19)
  }
  if (params_.estimate_drag_scale) {
    f.block<3, 1>(kV, kK) = lin0;  // the drag is linear in k
    f.block<3, 1>(kW, kK) = ang0;
  }
  return f;
}

void PoleFreeFlightEkf::step(double h, Propagation propagation) {
  if (propagation == Propagation::mean_only) {
    state_ = model::normalised_pole_state(model::pole_free_flight_step(state_, h, scaled_model()));
    return;
  }
  const StateCovariance f = jacobian();
  // G Q G^T: white accelerations on v and (normal to n) on Omega, a random walk of k.
  const Eigen::Matrix3d q_w =
      params_.angular_acceleration_psd * (Eigen::Matrix3d::Identity() - state_.n * state_.n.transpose());
  const double q_k = params_.estimate_drag_scale ? params_.drag_scale_psd : 0.0;
  StateCovariance m = StateCovariance::Zero();
  m.block<3, 3>(kV, kV) = params_.acceleration_psd * Eigen::Matrix3d::Identity();
  m.block<3, 3>(kW, kW) = q_w;
  m(kK, kK) = q_k;
  // F M from M's blocks (it is zero outside them).
  StateCovariance fm = StateCovariance::Zero();
  fm.middleCols<3>(kV) = params_.acceleration_psd * f.middleCols<3>(kV);
  fm.middleCols<3>(kW) = f.middleCols<3>(kW) * q_w;
  fm.col(kK) = q_k * f.col(kK);

  // Discretised to second order in h: Phi = I + F h + (F h)^2 / 2 and
  // Q_d = M h + (F M + M F^T) h^2 / 2 (the h^3 term is below 1e-3 of M h at 5 ms steps).
  // Nothing depends on the position, so F's first three columns are zero, and so are those of
  // G = Phi - I: Phi P Phi^T = A + A G^T with A = P + G P, each product over the ten others
  // (a third fewer multiplications than the full 13 x 13 ones, the same matrix to rounding).
  static_assert(kP == 0 && kV == 3, "the position's columns come first");
  constexpr int kMoving = kSize - kV;  // the columns of F that are not zero
  const StateCovariance fh = f * h;
  StateCovariance g = fh;
  g.rightCols<kMoving>() +=
      0.5 * small_product(fh.rightCols<kMoving>(), fh.bottomRightCorner<kMoving, kMoving>());
  const StateCovariance a = p_ + small_product(g.rightCols<kMoving>(), p_.bottomRows<kMoving>());
  const StateCovariance qd = m * h + 0.5 * h * h * (fm + fm.transpose());
  p_ = a + small_product(a.rightCols<kMoving>(), g.rightCols<kMoving>().transpose()) + qd;

  state_ = model::pole_free_flight_step(state_, h, scaled_model());
  normalise();
}

void PoleFreeFlightEkf::normalise() {
  state_ = model::normalised_pole_state(state_);
  normalise_covariance(state_, p_);
  p_ = 0.5 * (p_ + p_.transpose()).eval();
}

void PoleFreeFlightEkf::predict(double dt_s, Propagation propagation) {
  if (!(dt_s > 0.0) || !std::isfinite(dt_s)) return;
  const double max_step = params_.max_step_s > 0.0 ? params_.max_step_s : dt_s;
  const int steps = std::max(1, static_cast<int>(std::ceil(dt_s / max_step - 1e-9)));
  const double h = dt_s / steps;
  for (int i = 0; i < steps; ++i) step(h, propagation);
}

LinearisedPoleMeasurement<PoleFreeFlightEkf::kSize> PoleFreeFlightEkf::linearise(
    const PoleMeasurement& m) const {
  LinearisedPoleMeasurement<kSize> out;
  const Eigen::Matrix<double, 3, 2> b = tangent_basis(state_.n);
  out.nu.head<3>() = m.p_m - state_.p_m;
  out.nu.tail<2>() = b.transpose() * m.n;  // B^T n_pred = 0
  out.h.block<3, 3>(0, kP).setIdentity();
  out.h.block<2, 3>(3, kN) = b.transpose();
  out.r = pole_measurement_noise(params_.mocap_position_sigma_m, params_.mocap_direction_sigma_rad);
  return out;
}

PoleInnovation PoleFreeFlightEkf::innovation(const PoleMeasurement& measurement) const {
  return pole_innovation(linearise(measurement), p_);
}

PoleInnovation PoleFreeFlightEkf::update(const PoleMeasurement& measurement) {
  return update(measurement, innovation(measurement));
}

PoleInnovation PoleFreeFlightEkf::update(const PoleMeasurement& measurement, const PoleInnovation& inn) {
  if (!inn.valid) return inn;
  const LinearisedPoleMeasurement<kSize> m = linearise(measurement);
  const StateVector dx = kalman_correction(m, inn, p_);
  state_.p_m += dx.segment<3>(kP);
  state_.v_mps += dx.segment<3>(kV);
  state_.n += dx.segment<3>(kN);
  state_.omega_radps += dx.segment<3>(kW);
  if (params_.estimate_drag_scale) drag_scale_ = std::clamp(drag_scale_ + dx(kK), 0.0, kMaxDragScale);
  normalise();
  last_nis_ = inn.nis;
  return inn;
}

double free_flight_nees(const PoleFreeFlightEkf& ekf, const model::PoleState& truth) {
  const model::PoleState& s = ekf.state();
  const Eigen::Matrix<double, 3, 2> b = tangent_basis(s.n);
  Eigen::Matrix<double, 10, 12> j = Eigen::Matrix<double, 10, 12>::Zero();
  j.block<3, 3>(0, 0).setIdentity();
  j.block<3, 3>(3, 3).setIdentity();
  j.block<2, 3>(6, 6) = b.transpose();
  j.block<2, 3>(8, 9) = b.transpose();
  Eigen::Matrix<double, 12, 1> e;
  e << s.p_m - truth.p_m, s.v_mps - truth.v_mps, s.n - truth.n, s.omega_radps - truth.omega_radps;
  const Eigen::Matrix<double, 10, 1> e10 = j * e;
  const Eigen::Matrix<double, 10, 10> p10 = j * ekf.pole_covariance() * j.transpose();
  return e10.dot(p10.ldlt().solve(e10));
}

}  // namespace gs::estimation
