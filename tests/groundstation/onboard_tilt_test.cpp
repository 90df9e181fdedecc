// The vehicle's own attitude against motion capture's (groundstation/estimation/onboard_tilt.hpp):
// the correction is the on-board estimate's tilt whatever its heading, it is sent once a calm
// window's mean is off, and it puts the estimate's up where motion capture measures it.
#include <algorithm>
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "groundstation/estimation/onboard_tilt.hpp"
#include "pa/protocol.hpp"

using gs::estimation::OnboardTilt;

namespace {

Eigen::Quaterniond about(const Eigen::Vector3d& axis, double angle_rad) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle_rad, axis.normalized()));
}

// What the firmware does with the correction (fw::AttitudeEstimator::correct_tilt): the shortest
// rotation taking the true up onto +z, on the inertial side.
Eigen::Quaterniond corrected(const Eigen::Quaterniond& onboard, const Eigen::Vector2d& up_xy) {
  const Eigen::Vector3d up = Eigen::Vector3d(up_xy.x(), up_xy.y(), 1.0).normalized();
  return Eigen::Quaterniond::FromTwoVectors(up, Eigen::Vector3d::UnitZ()) * onboard;
}

// A vehicle swaying in hover (0.1 rad at 0.5 Hz about x, a slow yaw), its on-board estimate off
// by `error` on the inertial side and turned by its own heading.
struct Hover {
  Eigen::Quaterniond error = about(Eigen::Vector3d(1.0, -2.0, 0.0), 0.03);
  Eigen::Quaterniond frame =
      about(Eigen::Vector3d::UnitZ(), 2.0);  // its own heading, and the corrections taken
  Eigen::Quaterniond truth(double t_s) const {
    return about(Eigen::Vector3d::UnitZ(), 0.1 * t_s) *
           about(Eigen::Vector3d::UnitX(), 0.1 * std::sin(M_PI * t_s));
  }
  Eigen::Quaterniond onboard(double t_s) const { return frame * error * truth(t_s); }
};

}  // namespace

TEST_CASE("the correction puts the on-board up where motion capture has it, whatever the heading") {
  const Hover h;
  for (const double t_s : {0.0, 0.5, 1.3}) {
    const Eigen::Vector3d up = OnboardTilt::true_up_onboard(h.onboard(t_s), h.truth(t_s));
    const Eigen::Quaterniond fixed = corrected(h.onboard(t_s), up.head<2>() / up.z());
    const Eigen::Vector3d up_body_fixed = fixed.conjugate() * Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d up_body_true = h.truth(t_s).conjugate() * Eigen::Vector3d::UnitZ();
    CHECK((up_body_fixed - up_body_true).norm() < 1e-12);
    // Before, the on-board up was 0.03 rad off.
    const Eigen::Vector3d up_body_before = h.onboard(t_s).conjugate() * Eigen::Vector3d::UnitZ();
    CHECK(std::acos(up_body_before.dot(up_body_true)) == Approx(0.03).margin(1e-9));
  }
}

TEST_CASE("a calm second's mean off by more than the noise is sent once, then the reports settle") {
  Hover h;
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.003);  // motion capture's attitude noise, rad
  OnboardTilt tilt;
  int corrections = 0;
  for (int k = 0; k < 1000; ++k) {  // 10 s of reports every 10 ms
    const double t_s = 0.01 * k;
    const Eigen::Vector3d n(noise(rng), noise(rng), noise(rng));
    const Eigen::Quaterniond measured = h.truth(t_s) * about(n, n.norm());
    if (const auto up = tilt.report(t_s, h.onboard(t_s), measured, 0.2)) {
      ++corrections;
      CHECK(tilt.last_error_rad() == Approx(0.03).margin(0.002));
      h.frame = corrected(h.frame, *up);  // the vehicle takes it, in its own frame
    }
  }
  CHECK(corrections == 1);
  CHECK(tilt.last_error_rad() < 0.002);  // what is left is noise, below the threshold
}

TEST_CASE("fast turns, too few reports and nonsense are not judged; a large tilt is corrected in steps") {
  const Hover h;
  OnboardTilt tilt;
  for (int k = 0; k < 300; ++k)
    CHECK_FALSE(tilt.report(0.01 * k, h.onboard(0.01 * k), h.truth(0.01 * k), 3.0));
  for (int k = 0; k < 300; k += 10)
    CHECK_FALSE(tilt.report(0.01 * k, h.onboard(0.01 * k), h.truth(0.01 * k), 0.1));
  const Eigen::Quaterniond nan(NAN, 0.0, 0.0, 0.0);
  CHECK_FALSE(tilt.report(5.0, nan, h.truth(5.0), 0.1));
  CHECK_FALSE(tilt.report(NAN, h.onboard(5.0), h.truth(5.0), 0.1));

  Hover far = h;
  far.error = about(Eigen::Vector3d::UnitY(), 0.5);
  OnboardTilt big;
  std::optional<Eigen::Vector2d> up;
  for (int k = 0; k <= 100 && !up; ++k)
    up = big.report(0.01 * k, far.onboard(0.01 * k), far.truth(0.01 * k), 0.1);
  REQUIRE(up);
  CHECK(up->cwiseAbs().maxCoeff() > 0.4);  // as measured; the command bounds it

  const std::int32_t argument = gs::estimation::tilt_correction_argument(*up);
  CHECK(std::max(std::abs(pa::proto::tilt_x_counts(argument)),
                 std::abs(pa::proto::tilt_y_counts(argument))) == pa::proto::kTiltMaxCounts);
}

TEST_CASE("the command's argument carries the true up to 1e-4 and within the firmware's bound") {
  for (const Eigen::Vector2d& up :
       {Eigen::Vector2d(0.0123, -0.0456), Eigen::Vector2d(-0.2, 0.2), Eigen::Vector2d(0.0, -0.00004)}) {
    const std::int32_t a = gs::estimation::tilt_correction_argument(up);
    CHECK(pa::proto::tilt_x_counts(a) * 1e-4 == Approx(up.x()).margin(0.5e-4));
    CHECK(pa::proto::tilt_y_counts(a) * 1e-4 == Approx(up.y()).margin(0.5e-4));
  }
  const std::int32_t clamped = gs::estimation::tilt_correction_argument(Eigen::Vector2d(3.0, -3.0));
  CHECK(pa::proto::tilt_x_counts(clamped) == pa::proto::kTiltMaxCounts);
  CHECK(pa::proto::tilt_y_counts(clamped) == -pa::proto::kTiltMaxCounts);
}
