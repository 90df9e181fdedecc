// The pole filters of the hybrid estimator (free flight (20), on a vehicle (30)), their mode
// conversions and the plate's normal force, against the model and the independent truth world.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <random>

#include "estimation_test_world.hpp"
#include "groundstation/estimation/pole_free_flight_ekf.hpp"
#include "groundstation/estimation/pole_mode_conversion.hpp"
#include "groundstation/estimation/pole_on_vehicle_ekf.hpp"
#include "groundstation/model/impact.hpp"

namespace {

using estimation_test::World;
using estimation_test::WorldParams;
using gs::estimation::PoleCovariance;
using gs::estimation::PoleFreeFlightEkf;
using gs::estimation::PoleMeasurement;
using gs::estimation::PoleOnVehicleEkf;
using gs::model::PoleParams;
using gs::model::PoleState;

PoleState throw_like_state() {
  PoleState s;
  s.p_m = Eigen::Vector3d(1.5, 0.1, 2.3);
  s.v_mps = Eigen::Vector3d(0.3, 0.05, 5.5);
  s.n = Eigen::Vector3d(std::sin(0.48), 0.0, std::cos(0.48));
  s.omega_radps = Eigen::Vector3d(0.1, 2.5, 0.0);
  return gs::model::normalised_pole_state(s);
}

PoleCovariance diagonal_covariance(double sp, double sv, double sn, double sw) {
  PoleCovariance p = PoleCovariance::Zero();
  p.diagonal() << sp * sp, sp * sp, sp * sp, sv * sv, sv * sv, sv * sv, sn * sn, sn * sn, sn * sn, sw * sw,
      sw * sw, sw * sw;
  return p;
}

PoleMeasurement measure(const estimation_test::Pose& pose) {
  return {pose.p, pose.q * Eigen::Vector3d::UnitZ()};
}

struct FlightStats {
  double mean_nis = 0.0;
  double mean_nees = 0.0;
  double final_position_error_m = 0.0;
  double drag_scale = 1.0;
};

// A free flight of the world's pole (broadside, spinning), filtered from a perturbed start.
FlightStats filter_free_flight(const gs::estimation::PoleFreeFlightEkfParams& params, unsigned seed,
                               double duration_s, double skip_s) {
  World w(WorldParams{}, seed);
  w.vehicle(0).p = Eigen::Vector3d(10, 0, 0);
  w.vehicle(1).p = Eigen::Vector3d(-10, 0, 0);
  const Eigen::Vector3d v0(1.5, 0.3, 5.0);
  const Eigen::Vector3d n0 = Eigen::Vector3d(0.6, 0.0, 0.8).normalized();
  const Eigen::Vector3d w0(0.0, 3.0, 0.5);
  w.place_pole_free(Eigen::Vector3d(0, 0, 2), v0, n0, w0);
  PoleFreeFlightEkf ekf(params);
  const estimation_test::Frame f0 = w.frame();
  PoleState start;
  start.p_m = f0.pole.p;
  start.v_mps = f0.truth.v + Eigen::Vector3d(0.05, -0.03, 0.04);
  start.n = f0.pole.q * Eigen::Vector3d::UnitZ();
  start.omega_radps = f0.truth.omega + Eigen::Vector3d(0.05, -0.05, 0.0);
  ekf.reset(start, diagonal_covariance(1e-3, 0.06, 1e-3, 0.08), 1.0, 0.3);
  FlightStats s;
  int n = 0;
  const int frames = static_cast<int>(duration_s / 0.005);
  for (int k = 1; k <= frames; ++k) {
    for (int i = 0; i < w.params().steps_per_frame; ++i) w.step();
    ekf.predict(0.005);
    const estimation_test::Frame f = w.frame();
    const gs::estimation::PoleInnovation inn = ekf.update(measure(f.pole));
    REQUIRE(inn.valid);
    if (f.t_s < skip_s) continue;
    PoleState truth;
    truth.p_m = f.truth.p;
    truth.v_mps = f.truth.v;
    truth.n = f.truth.n;
    truth.omega_radps = f.truth.omega;
    s.mean_nis += inn.nis;
    s.mean_nees += gs::estimation::free_flight_nees(ekf, truth);
    s.final_position_error_m = (ekf.state().p_m - truth.p_m).norm();
    ++n;
  }
  s.mean_nis /= n;
  s.mean_nees /= n;
  s.drag_scale = ekf.drag_scale();
  return s;
}

}  // namespace

TEST_CASE("the free-flight EKF predicts with the model of eq. (20)", "[estimation]") {
  gs::estimation::PoleFreeFlightEkfParams params;
  PoleFreeFlightEkf ekf(params);
  const PoleState s0 = throw_like_state();
  ekf.reset(s0, diagonal_covariance(1e-3, 0.01, 1e-3, 0.01), 1.0, 0.1);
  const double trace0 = ekf.covariance().trace();
  ekf.predict(0.1);
  const PoleState ref = gs::model::propagate_pole(s0, 0.1, 0.005, params.pole);
  CHECK((ekf.state().p_m - ref.p_m).norm() < 1e-12);
  CHECK((ekf.state().n - ref.n).norm() < 1e-12);
  CHECK(ekf.covariance().trace() > trace0);
  // The covariance carries no uncertainty along the linearised constraints |n| = 1
  // (n . dn = 0) and Omega . n = 0 (n . dOmega + Omega . dn = 0).
  const Eigen::Vector3d n = ekf.state().n;
  const Eigen::Vector3d w = ekf.state().omega_radps;
  Eigen::Matrix<double, 1, 13> radial = Eigen::Matrix<double, 1, 13>::Zero();
  radial.segment<3>(6) = n.transpose();
  Eigen::Matrix<double, 1, 13> axial = Eigen::Matrix<double, 1, 13>::Zero();
  axial.segment<3>(6) = w.transpose();
  axial.segment<3>(9) = n.transpose();
  CHECK((radial * ekf.covariance() * radial.transpose())(0, 0) == Approx(0.0).margin(1e-15));
  CHECK((axial * ekf.covariance() * axial.transpose())(0, 0) == Approx(0.0).margin(1e-12));
  CHECK(ekf.covariance().block<3, 3>(9, 9).trace() > 1e-4);  // the rest is there
}

TEST_CASE("the free-flight Jacobian matches central differences of eq. (20)", "[estimation]") {
  gs::estimation::PoleFreeFlightEkfParams params;
  PoleFreeFlightEkf ekf(params);
  const PoleState s0 = throw_like_state();
  const double k = 1.2;
  ekf.reset(s0, diagonal_covariance(1e-3, 0.01, 1e-3, 0.01), k, 0.1);
  const PoleFreeFlightEkf::StateCovariance f = ekf.jacobian();
  PoleParams scaled = params.pole;
  scaled.drag_axial *= k;
  scaled.drag_normal *= k;
  scaled.drag_rotational *= k;
  const auto flat = [](const PoleState& d) {
    Eigen::Matrix<double, 12, 1> v;
    v << d.p_m, d.v_mps, d.n, d.omega_radps;
    return v;
  };
  for (int c = 0; c < 12; ++c) {
    const double eps = 1e-5;
    Eigen::Matrix<double, 12, 1> xp = flat(s0);
    Eigen::Matrix<double, 12, 1> xm = flat(s0);
    xp(c) += eps;
    xm(c) -= eps;
    const auto unflat = [](const Eigen::Matrix<double, 12, 1>& v) {
      PoleState s;
      s.p_m = v.segment<3>(0);
      s.v_mps = v.segment<3>(3);
      s.n = v.segment<3>(6);
      s.omega_radps = v.segment<3>(9);
      return s;
    };
    const Eigen::Matrix<double, 12, 1> col =
        (flat(gs::model::pole_free_flight_derivative(unflat(xp), scaled)) -
         flat(gs::model::pole_free_flight_derivative(unflat(xm), scaled))) /
        (2.0 * eps);
    CHECK((f.col(c).head<12>() - col).norm() < 1e-4 * (1.0 + col.norm()));
  }
  // d/dk: the drag at k = 1.
  const PoleState d1 = gs::model::pole_free_flight_derivative(s0, params.pole);
  const PoleState d0 = gs::model::pole_free_flight_derivative(s0, gs::model::without_drag(params.pole));
  CHECK((f.block<3, 1>(3, 12) - (d1.v_mps - d0.v_mps)).norm() < 1e-9);
  // Nothing depends on the position: the covariance step multiplies over the other ten columns
  // only (PoleFreeFlightEkf::step), exactly so while these are zero.
  CHECK(f.leftCols<3>().isZero(0.0));
}

// kalman_correction forms the Joseph update from products with the measurement's five columns;
// it is the textbook (I - K H) P (I - K H)^T + K R K^T, K = P H^T S^-1, to rounding.
TEST_CASE("the Kalman correction's Joseph update is the textbook one", "[estimation]") {
  constexpr int N = PoleFreeFlightEkf::kSize;
  std::mt19937_64 rng(7);
  std::normal_distribution<double> gauss;
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::Matrix<double, N, N> a;
    for (double& x : a.reshaped()) x = gauss(rng);
    const Eigen::Matrix<double, N, N> p0 = a * a.transpose() + 0.1 * Eigen::Matrix<double, N, N>::Identity();
    gs::estimation::LinearisedPoleMeasurement<N> m;
    for (double& x : m.h.reshaped()) x = gauss(rng);
    for (double& x : m.nu) x = gauss(rng);
    m.r = gs::estimation::pole_measurement_noise(0.002, 0.01);
    const gs::estimation::PoleInnovation inn = gs::estimation::pole_innovation(m, p0);
    REQUIRE(inn.valid);
    Eigen::Matrix<double, N, N> p = p0;
    const Eigen::Matrix<double, N, 1> dx = gs::estimation::kalman_correction(m, inn, p);

    const Eigen::Matrix<double, N, 5> k = p0 * m.h.transpose() * inn.s.inverse();
    const Eigen::Matrix<double, N, N> ikh = Eigen::Matrix<double, N, N>::Identity() - k * m.h;
    const Eigen::Matrix<double, N, N> joseph = ikh * p0 * ikh.transpose() + k * m.r * k.transpose();
    CHECK((p - joseph).norm() < 1e-10 * p0.norm());
    CHECK((p - p.transpose()).norm() == 0.0);
    CHECK((dx - k * m.nu).norm() < 1e-10 * (1.0 + dx.norm()));
  }
}

TEST_CASE("the free-flight EKF is consistent on the truth world's flight", "[estimation]") {
  gs::estimation::PoleFreeFlightEkfParams params;
  double nis = 0.0;
  double nees = 0.0;
  const int runs = 8;
  for (int r = 0; r < runs; ++r) {
    const FlightStats s = filter_free_flight(params, 100 + r, 0.8, 0.1);
    nis += s.mean_nis / runs;
    nees += s.mean_nees / runs;
    CHECK(s.final_position_error_m < 2e-3);
  }
  std::printf("free-flight EKF, true drag, %d flights of 0.8 s: mean NIS %.2f (5 dof), mean NEES "
              "%.2f (10 dof)\n",
              runs, nis, nees);
  CHECK(nis > 4.0);
  CHECK(nis < 6.0);
  CHECK(nees > 7.0);
  CHECK(nees < 13.0);
}

TEST_CASE("the drag scale is estimated online", "[estimation]") {
  gs::estimation::PoleFreeFlightEkfParams params;
  for (double* c : {&params.pole.drag_axial, &params.pole.drag_normal, &params.pole.drag_rotational}) {
    *c *= 1.3;  // the model's coefficients 30 % high: the truth is k = 1 / 1.3
  }
  double k_mean = 0.0;
  const int runs = 4;
  for (int r = 0; r < runs; ++r) k_mean += filter_free_flight(params, 200 + r, 0.8, 0.1).drag_scale / runs;
  std::printf("drag scale after 0.8 s of flight with the coefficients 30%% high: %.3f (truth "
              "%.3f)\n",
              k_mean, 1.0 / 1.3);
  CHECK(k_mean == Approx(1.0 / 1.3).margin(0.08));
}

TEST_CASE("the plate's normal force is the planar formula of docs/paper-notes.md", "[estimation]") {
  const PoleParams params;
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 100; ++i) {
    const double alpha = 0.8 * u(rng);
    const double alpha_dot = 3.0 * u(rng);
    const double theta = 0.6 * u(rng);
    const double a_q = 10.0 + 8.0 * u(rng);
    const double l = params.half_length_m;
    const gs::model::PoleOnVehicleState pole{l * std::sin(alpha), 0.0, l * std::cos(alpha) * alpha_dot, 0.0};
    const Eigen::Vector3d t(std::sin(theta), 0.0, std::cos(theta));
    const double d = alpha - theta;
    const double expected =
        a_q - 0.75 * a_q * std::sin(d) * std::sin(d) - l * alpha_dot * alpha_dot * std::cos(d);
    CHECK(gs::estimation::pole_normal_force_per_mass_mps2(pole, a_q * t, t, params) ==
          Approx(expected).margin(1e-9));
  }
  // Hovering upright: the pole's whole weight.
  CHECK(gs::estimation::pole_normal_force_per_mass_mps2({}, Eigen::Vector3d(0, 0, 9.81),
                                                        Eigen::Vector3d::UnitZ(), params) == Approx(9.81));
}

TEST_CASE("the on-vehicle EKF follows a pole balanced on the world's vehicle", "[estimation]") {
  const estimation_test::Recording rec = estimation_test::record_balanced_hover(WorldParams{}, 21, 4.0);
  gs::estimation::VehicleObserver vehicle;
  PoleOnVehicleEkf ekf;
  bool started = false;
  double nis = 0.0;
  double fn_error = 0.0;
  double angle_error = 0.0;
  int n = 0;
  for (const estimation_test::Frame& f : rec.frames) {
    gs::estimation::MocapPose pose;
    pose.p_m = f.vehicle[0].p;
    pose.q = f.vehicle[0].q;
    vehicle.update(pose);
    const gs::estimation::PlateKinematics plate = vehicle.plate();
    const PoleMeasurement m = measure(f.pole);
    if (!started) {
      PoleState s;
      s.p_m = m.p_m;
      s.n = m.n;
      const auto seed = gs::estimation::on_vehicle_seed_from_free_flight(
          s, diagonal_covariance(1e-3, 1.0, 1e-3, 1.0), plate, PoleParams{}, {});
      REQUIRE(seed);
      ekf.reset(seed->state, seed->covariance, seed->direction_sign);
      started = true;
    } else {
      const gs::estimation::PoleInnovation inn = ekf.update(m, plate);
      if (f.t_s > 0.5) {
        nis += inn.nis;
        fn_error += std::abs(ekf.normal_force(plate).value_mps2 - f.truth.normal_force_per_mass);
        angle_error += std::acos(std::min(1.0, ekf.free_flight_state(plate).n.dot(f.truth.n)));
        ++n;
      }
    }
    const gs::model::VehicleInput in{f.command[0].thrust_mps2, f.command[0].rates_radps};
    vehicle.predict(0.005, &in);
    ekf.predict(0.005, vehicle.plate().a_mps2);
  }
  std::printf("on-vehicle EKF, balanced hover: mean NIS %.2f (5 dof), mean |F_N error| %.3f "
              "m/s^2, mean direction error %.2f mrad\n",
              nis / n, fn_error / n, 1e3 * angle_error / n);
  CHECK(ekf.valid());
  CHECK(nis / n < 8.0);
  CHECK(fn_error / n < 0.5);
  CHECK(angle_error / n < 1e-3);
}

TEST_CASE("mode conversions round-trip and the impact seed is the impact map", "[estimation]") {
  const PoleParams params;
  gs::estimation::PlateKinematics plate;
  plate.p_m = Eigen::Vector3d(1.0, 0.2, 1.4);
  plate.v_mps = Eigen::Vector3d(0.1, 0.0, -0.2);
  plate.inertial_from_body = Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  // A pole whose head end rests on the plate (n pointing down to it), 2 cm off centre.
  const Eigen::Vector3d n_pivot = Eigen::Vector3d(0.3, -0.1, 1.0).normalized();
  const Eigen::Vector3d contact = plate.p_m + plate.inertial_from_body.col(0) * 0.02;
  PoleState s;
  s.n = -n_pivot;
  s.p_m = contact + params.half_length_m * n_pivot;
  s.omega_radps = Eigen::Vector3d(0.5, 1.5, 0.0);
  s = gs::model::normalised_pole_state(s);
  s.v_mps = plate.v_mps + params.half_length_m * s.omega_radps.cross(n_pivot);
  const PoleCovariance p = diagonal_covariance(1e-3, 0.01, 1e-3, 0.01);
  const auto seed = gs::estimation::on_vehicle_seed_from_free_flight(s, p, plate, params, {});
  REQUIRE(seed);
  CHECK(seed->direction_sign == -1.0);
  CHECK(seed->state(4) == Approx(0.02).margin(1e-12));
  PoleOnVehicleEkf ekf;
  ekf.reset(seed->state, seed->covariance, seed->direction_sign);
  const gs::estimation::FreeFlightSeed back = gs::estimation::free_flight_seed_from_on_vehicle(ekf, plate);
  CHECK((back.state.p_m - s.p_m).norm() < 1e-12);
  CHECK((back.state.v_mps - s.v_mps).norm() < 1e-12);
  CHECK((back.state.n - s.n).norm() < 1e-12);
  CHECK((back.state.omega_radps - s.omega_radps).norm() < 1e-12);
  // Far from the plate: no seed.
  PoleState away = s;
  away.p_m.z() += 0.2;
  CHECK_FALSE(gs::estimation::on_vehicle_seed_from_free_flight(away, p, plate, params, {}));

  // The impact seed is model::impact_map.
  PoleState falling = s;
  falling.v_mps = Eigen::Vector3d(0.4, 0.0, -3.0);
  const gs::model::ImpactResult r = gs::model::impact_map(falling, plate.v_mps, params);
  const gs::estimation::OnVehicleSeed impact =
      gs::estimation::on_vehicle_seed_after_impact(falling, p, plate, params, 0.2);
  CHECK(impact.state(0) == Approx(r.on_vehicle.a_m));
  CHECK(impact.state(2) == Approx(r.on_vehicle.a_dot_mps));
  CHECK(impact.state(3) == Approx(r.on_vehicle.b_dot_mps));
  CHECK(impact.covariance(2, 2) > 0.2 * 0.2);
}

TEST_CASE("a vehicle with slower motors or in noisier poses trusts them less", "[estimation]") {
  const gs::estimation::PoleTrust trust;
  using gs::estimation::pole_measurement_sigma;
  const double nan = std::nan("");
  const double quiet = 0.5e-3;
  // By the lag, in quiet poses.
  CHECK(pole_measurement_sigma(0.020, quiet, trust) == trust.trusting_sigma);
  CHECK(pole_measurement_sigma(trust.fast_lag_s, quiet, trust) == trust.trusting_sigma);
  const double middle_s = 0.5 * (trust.fast_lag_s + trust.slow_lag_s);
  const double halfway = 0.5 * (trust.trusting_sigma + trust.wary_sigma);
  CHECK(pole_measurement_sigma(middle_s, quiet, trust) == Approx(halfway));
  CHECK(pole_measurement_sigma(trust.slow_lag_s, quiet, trust) == trust.wary_sigma);
  CHECK(pole_measurement_sigma(0.080, quiet, trust) == trust.wary_sigma);
  // By the noise, with fast motors; the larger of the two wins.
  CHECK(pole_measurement_sigma(0.030, 0.5 * (trust.quiet_noise + trust.noisy_noise), trust) ==
        Approx(halfway));
  CHECK(pole_measurement_sigma(0.030, trust.noisy_noise, trust) == trust.wary_sigma);
  CHECK(pole_measurement_sigma(middle_s, trust.noisy_noise, trust) == trust.wary_sigma);
  // Unknown lag or noise: trusted.
  CHECK(pole_measurement_sigma(nan, nan, trust) == trust.trusting_sigma);
}

TEST_CASE("an on-vehicle EKF that trusts the poses less moves less towards one, judged as any other",
          "[estimation]") {
  // Both filters start from the same upright pole; one pose 5 mm aside pulls each.
  gs::estimation::PlateKinematics plate;
  plate.p_m = Eigen::Vector3d(0.0, 0.0, 1.0);
  PoleState s;
  s.n = Eigen::Vector3d::UnitZ();
  s.p_m = plate.p_m + PoleParams{}.half_length_m * s.n;
  const auto seed = gs::estimation::on_vehicle_seed_from_free_flight(
      s, diagonal_covariance(1e-3, 0.1, 1e-3, 0.1), plate, PoleParams{}, {});
  REQUIRE(seed);
  PoleOnVehicleEkf trusting;
  PoleOnVehicleEkf wary;
  wary.set_measurement_sigma(3e-3, 3e-3);
  CHECK(wary.gain_position_sigma_m() == 3e-3);
  CHECK(wary.gain_direction_sigma_rad() == 3e-3);
  trusting.reset(seed->state, seed->covariance, seed->direction_sign);
  wary.reset(seed->state, seed->covariance, seed->direction_sign);
  PoleMeasurement m{s.p_m, s.n};
  m.p_m.x() += 0.005;
  // The gain's innovation covariance is the wary one, the evidence the same: the mode selector
  // judges both against the same motion capture.
  const gs::estimation::PoleInnovation inn_trusting = trusting.innovation(m, plate);
  const gs::estimation::PoleInnovation inn_wary = wary.innovation(m, plate);
  REQUIRE(inn_trusting.valid);
  REQUIRE(inn_wary.valid);
  CHECK(inn_wary.s(0, 0) > inn_trusting.s(0, 0) + 7e-6);
  CHECK(inn_wary.nis == Approx(inn_trusting.nis).epsilon(1e-9));
  CHECK(inn_wary.log_likelihood == Approx(inn_trusting.log_likelihood).epsilon(1e-9));
  trusting.update(m, plate);
  wary.update(m, plate);
  const double moved_trusting = (trusting.state() - seed->state).norm();
  const double moved_wary = (wary.state() - seed->state).norm();
  CHECK(moved_trusting > 0.0);
  CHECK(moved_wary < 0.5 * moved_trusting);
}
