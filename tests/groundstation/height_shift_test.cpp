// The catch height's shift (groundstation/planning/height_shift.hpp): from rest to a target at
// rest, re-planned from its own state without a jump, its acceleration within the bound (the
// move cut where it is not), and the shifted reference's feed-forward.
#include "groundstation/planning/height_shift.hpp"

#include <catch2/catch.hpp>
#include <cmath>

using gs::planning::HeightShift;
using gs::planning::HeightShiftSample;

namespace {

double peak_accel(const HeightShift& shift, double from_s, double to_s) {
  double peak = 0.0;
  for (double t = from_s; t <= to_s; t += 1e-4) peak = std::max(peak, std::abs(shift.at(t).ddz_mps2));
  return peak;
}

}  // namespace

TEST_CASE("No shift is zero at all times") {
  const HeightShift shift;
  for (double t : {-1.0, 0.0, 3.0}) {
    const HeightShiftSample s = shift.at(t);
    CHECK(s.z_m == 0.0);
    CHECK(s.dz_mps == 0.0);
    CHECK(s.ddz_mps2 == 0.0);
  }
}

TEST_CASE("A shift goes from rest to its target at rest at the end") {
  HeightShift shift;
  shift.retarget(1.0, 0.4, 1.8, 100.0);
  CHECK(shift.target_m() == 0.4);
  CHECK(shift.at(1.0).z_m == Approx(0.0).margin(1e-12));
  CHECK(shift.at(1.0).dz_mps == Approx(0.0).margin(1e-12));
  CHECK(shift.at(1.0).ddz_mps2 == Approx(0.0).margin(1e-12));
  CHECK(shift.at(1.8 - 1e-9).z_m == Approx(0.4).margin(1e-6));
  CHECK(shift.at(1.8 - 1e-9).dz_mps == Approx(0.0).margin(1e-6));
  CHECK(shift.at(1.8 - 1e-9).ddz_mps2 == Approx(0.0).margin(1e-5));
  CHECK(shift.at(2.5).z_m == 0.4);
  CHECK(shift.at(2.5).dz_mps == 0.0);
  // Half-way, by symmetry, half the way at the peak rate 15/8 h/T.
  CHECK(shift.at(1.4).z_m == Approx(0.2));
  CHECK(shift.at(1.4).dz_mps == Approx(15.0 / 8.0 * 0.4 / 0.8));
  // Its derivatives are its samples' (central differences).
  const double h = 1e-5;
  const HeightShiftSample s = shift.at(1.3);
  CHECK(s.dz_mps == Approx((shift.at(1.3 + h).z_m - shift.at(1.3 - h).z_m) / (2 * h)).epsilon(1e-6));
  CHECK(s.ddz_mps2 == Approx((shift.at(1.3 + h).dz_mps - shift.at(1.3 - h).dz_mps) / (2 * h)).epsilon(1e-6));
  CHECK(s.jerk_mps3 ==
        Approx((shift.at(1.3 + h).ddz_mps2 - shift.at(1.3 - h).ddz_mps2) / (2 * h)).epsilon(1e-6));
}

TEST_CASE("A new target is taken from the shift's state then, without a jump") {
  HeightShift shift;
  shift.retarget(0.0, 0.5, 1.0, 100.0);
  const HeightShiftSample before = shift.at(0.4);
  shift.retarget(0.4, -0.2, 1.0, 100.0);
  const HeightShiftSample after = shift.at(0.4);
  CHECK(after.z_m == Approx(before.z_m));
  CHECK(after.dz_mps == Approx(before.dz_mps));
  CHECK(after.ddz_mps2 == Approx(before.ddz_mps2));
  CHECK(shift.at(1.0).z_m == -0.2);
  // The same target again keeps the same course.
  const double midway = shift.at(0.7).z_m;
  shift.retarget(0.5, -0.2, 1.0, 100.0);
  CHECK(shift.at(0.7).z_m == Approx(midway).margin(1e-12));
}

TEST_CASE("A move beyond the acceleration bound is cut to the largest within it") {
  HeightShift shift;
  shift.retarget(0.0, 1.0, 0.5, 6.0);  // a metre in 0.5 s needs 5.77 h / T^2 = 23 m/s^2
  CHECK(shift.target_m() > 0.1);
  CHECK(shift.target_m() < 0.3);
  CHECK(peak_accel(shift, 0.0, 0.5) <= 6.0 + 1e-6);
  CHECK(peak_accel(shift, 0.0, 0.5) > 5.9);
  // Within the bound the target is taken whole.
  HeightShift gentle;
  gentle.retarget(0.0, 0.2, 0.5, 6.0);
  CHECK(gentle.target_m() == 0.2);
}

TEST_CASE("A retarget too close to the end, or not finite, keeps the course") {
  HeightShift shift;
  shift.retarget(0.0, 0.3, 1.0, 100.0);
  const double at = shift.at(0.98).z_m;
  shift.retarget(0.97, 0.0, 1.0, 100.0);
  CHECK(shift.target_m() == 0.3);
  CHECK(shift.at(0.98).z_m == at);
  shift.retarget(0.2, std::nan(""), 1.0, 100.0);
  shift.retarget(0.2, 0.1, 1.0, 0.0);
  CHECK(shift.target_m() == 0.3);
}

TEST_CASE("The shifted reference is higher and its feed-forward follows the shift") {
  gs::planning::CatchReference ref;
  ref.position_m = Eigen::Vector3d(1.0, 2.0, 3.0);
  ref.acceleration_mps2 = Eigen::Vector3d(0.5, 0.0, -2.0);
  HeightShiftSample s;
  s.z_m = 0.2;
  s.dz_mps = 0.3;
  s.ddz_mps2 = 1.5;
  s.jerk_mps3 = 4.0;
  const gs::planning::CatchReference out = gs::planning::shifted(ref, s);
  CHECK(out.position_m.z() == Approx(3.2));
  CHECK(out.velocity_mps.z() == Approx(0.3));
  CHECK(out.acceleration_mps2.z() == Approx(-0.5));
  const gs::planning::NominalInputs u =
      gs::planning::nominal_inputs(Eigen::Vector3d(0.5, 0.0, -0.5), Eigen::Vector3d(0.0, 0.0, 4.0), 0.0);
  CHECK(out.thrust_mps2 == Approx(u.thrust_mps2));
  CHECK(out.pitch_rad == Approx(u.pitch_rad));
  CHECK((out.body_rates_radps - u.body_rates_radps).norm() < 1e-12);
}
