// The catch-point predictor (Section V): where and when the lower end crosses the catching
// height on the way down, against a fine-step reference, closed forms, and the catching instant.
#include "groundstation/planning/catch_point_predictor.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <random>

#include "groundstation/planning/catching_instant.hpp"

namespace {

using gs::model::PoleParams;
using gs::model::PoleState;
using gs::planning::CatchPointPrediction;

constexpr double kL = pa::kPoleHalfLength_m;
constexpr double kG = pa::kGravity_mps2;

struct Reference {
  bool found = false;
  double t_s = 0.0;
  Eigen::Vector3d lower_end = Eigen::Vector3d::Zero();
};

// 0.1 ms RK4 steps and linear interpolation of the crossing between them (the lower end moves
// < 1 mm per step; the interpolation error is ~ z'' dt^2 / 8, about 1e-8 m).
Reference reference_crossing(const PoleState& start, double height, const PoleParams& params,
                             double horizon_s) {
  const double dt = 1e-4;
  PoleState s = gs::model::normalised_pole_state(start);
  Eigen::Vector3d low = gs::model::pole_lower_end_m(s, params);
  for (int i = 0; i * dt < horizon_s; ++i) {
    const PoleState next = gs::model::pole_free_flight_step(s, dt, params);
    const Eigen::Vector3d next_low = gs::model::pole_lower_end_m(next, params);
    if (low.z() > height && next_low.z() <= height) {
      const double f = (low.z() - height) / (low.z() - next_low.z());
      return {true, (i + f) * dt, low + f * (next_low - low)};
    }
    s = next;
    low = next_low;
  }
  return {};
}

}  // namespace

TEST_CASE("the predictor agrees with a fine-step reference within 1 mm", "[predictor]") {
  const PoleParams params;
  const PoleState launch = gs::planning::pole_state_at_launch(gs::planning::fig5_launch_state(), params);
  std::mt19937 rng(31);
  std::normal_distribution<double> n01;
  double worst_xy = 0.0;
  double worst_t = 0.0;
  int found = 0;
  for (int i = 0; i < 40; ++i) {
    // Throw-like states perturbed in 3D (rates up to ~8 rad/s), at the launch and mid-flight.
    PoleState s = launch;
    s.v_mps += Eigen::Vector3d(n01(rng), n01(rng), n01(rng));
    s.omega_radps += 2.0 * Eigen::Vector3d(n01(rng), n01(rng), n01(rng));
    s = gs::model::normalised_pole_state(s);
    if (i % 2 == 1) s = gs::model::propagate_pole(s, 0.4, 0.01, params);
    const double height = 1.0 + 0.5 * n01(rng);
    const CatchPointPrediction p = gs::planning::predict_catch_point(s, height, params);
    const Reference ref = reference_crossing(s, height, params, 3.0);
    INFO("sample " << i);
    REQUIRE(p.found == ref.found);
    if (!p.found) continue;
    ++found;
    const double xy = std::hypot(p.x_m - ref.lower_end.x(), p.y_m - ref.lower_end.y());
    CHECK(xy < 1e-3);
    CHECK(std::abs(p.t_s - ref.t_s) < 1e-3);
    // The returned state is the pole at the crossing.
    const Eigen::Vector3d low = gs::model::pole_lower_end_m(p.state, params);
    CHECK(low.z() == Approx(height).margin(1e-6));
    CHECK(low.x() == p.x_m);
    CHECK(low.y() == p.y_m);
    worst_xy = std::max(worst_xy, xy);
    worst_t = std::max(worst_t, std::abs(p.t_s - ref.t_s));
  }
  CHECK(found > 30);
  std::printf("catch-point predictor vs 0.1 ms reference: worst catch-point error %.2e m, "
              "time %.2e s (%d crossings)\n",
              worst_xy, worst_t, found);
}

TEST_CASE("the predictor at the nominal catching height reproduces the catching instant", "[predictor]") {
  const PoleParams params;
  const PoleState launch = gs::planning::pole_state_at_launch(gs::planning::fig5_launch_state(), params);
  const gs::planning::CatchingInstant ci = gs::planning::find_catching_instant(launch, params);
  REQUIRE(ci.found);
  const CatchPointPrediction p = gs::planning::predict_catch_point(launch, ci.catch_height_m, params);
  REQUIRE(p.found);
  CHECK(p.t_s == Approx(ci.t_s).margin(1e-5));
  CHECK(p.x_m == Approx(ci.catch_point_m.x()).margin(1e-4));
  CHECK(p.y_m == Approx(ci.catch_point_m.y()).margin(1e-9));
}

TEST_CASE("free fall without drag matches the closed form", "[predictor]") {
  const PoleParams params = gs::model::without_drag(PoleParams{});
  // A pole not turning: the lower end follows z0 + vz t - g t^2 / 2.
  PoleState s;
  s.n = Eigen::Vector3d(0.3, -0.2, 0.9).normalized();
  s.p_m = Eigen::Vector3d(0.4, 0.1, 2.0);
  s.v_mps = Eigen::Vector3d(0.8, -0.3, 3.0);
  const double height = 1.2;
  const double z0 = s.p_m.z() - kL * s.n.z();
  // z0 + vz t - g t^2 / 2 = height, the later root.
  const double t = (s.v_mps.z() + std::sqrt(s.v_mps.z() * s.v_mps.z() + 2 * kG * (z0 - height))) / kG;
  const CatchPointPrediction p = gs::planning::predict_catch_point(s, height, params);
  REQUIRE(p.found);
  // RK4 is exact for this motion; what is left is the crossing search (height within 1e-7 m).
  CHECK(p.t_s == Approx(t).margin(1e-8));
  CHECK(p.x_m == Approx(s.p_m.x() - kL * s.n.x() + s.v_mps.x() * t).margin(1e-8));
  CHECK(p.y_m == Approx(s.p_m.y() - kL * s.n.y() + s.v_mps.y() * t).margin(1e-8));
  // Turning too: compare with the closed-form flight (ballistic centre, uniform rotation),
  // bisected on the lower end's height.
  s.omega_radps = Eigen::Vector3d(0.0, 2.5, 0.0);
  s = gs::model::normalised_pole_state(s);
  const auto at = [&](double tt) {
    PoleState x = s;
    x.p_m = s.p_m + s.v_mps * tt + 0.5 * Eigen::Vector3d(0, 0, -kG) * tt * tt;
    const double angle = s.omega_radps.norm() * tt;
    const Eigen::Vector3d k = s.omega_radps.normalized();
    x.n = s.n * std::cos(angle) + k.cross(s.n) * std::sin(angle) + k * k.dot(s.n) * (1.0 - std::cos(angle));
    return gs::model::pole_lower_end_m(x, params);
  };
  double lo = 0.0;
  while (!(at(lo).z() > height && at(lo + 1e-3).z() <= height)) lo += 1e-3;
  double hi = lo + 1e-3;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (at(mid).z() > height ? lo : hi) = mid;
  }
  const CatchPointPrediction q = gs::planning::predict_catch_point(s, height, params);
  REQUIRE(q.found);
  CHECK(q.t_s == Approx(0.5 * (lo + hi)).margin(1e-7));
  CHECK(q.x_m == Approx(at(q.t_s).x()).margin(1e-6));
  CHECK(q.y_m == Approx(at(q.t_s).y()).margin(1e-6));
}

TEST_CASE("no crossing on the way down: not found", "[predictor]") {
  const PoleParams params;
  PoleState s;
  s.n = Eigen::Vector3d::UnitZ();
  s.p_m = Eigen::Vector3d(0.0, 0.0, 1.0);
  // Already below the height and going down.
  s.v_mps = Eigen::Vector3d(0.5, 0.0, -2.0);
  CHECK_FALSE(gs::planning::predict_catch_point(s, 1.5, params).found);
  // Rising, but not up to the height: the apex of the lower end is below it.
  s.v_mps = Eigen::Vector3d(0.0, 0.0, 2.0);
  CHECK_FALSE(gs::planning::predict_catch_point(s, 1.0, params).found);
  // Above the height, but the crossing lies beyond the horizon: 59 m of fall take more than
  // sqrt(2 * 59 / g) = 3.5 s.
  s.p_m.z() = 60.0 + kL;
  s.v_mps = Eigen::Vector3d::Zero();
  gs::planning::CatchPointPredictorOptions options;
  CHECK_FALSE(gs::planning::predict_catch_point(s, 1.0, params, options).found);  // 3 s horizon
  options.horizon_s = 6.0;
  const CatchPointPrediction later = gs::planning::predict_catch_point(s, 1.0, params, options);
  CHECK(later.found);
  CHECK(later.t_s > std::sqrt(2.0 * 59.0 / kG));
  // Invalid arguments.
  CHECK_FALSE(gs::planning::predict_catch_point(s, std::nan(""), params).found);
  options.step_s = 0.0;
  CHECK_FALSE(gs::planning::predict_catch_point(s, 1.0, params, options).found);
}

TEST_CASE("a pole starting below the height is caught on its way back down", "[predictor]") {
  const PoleParams params = gs::model::without_drag(PoleParams{});
  PoleState s;
  s.n = Eigen::Vector3d::UnitZ();
  s.p_m = Eigen::Vector3d(0.0, 0.0, 1.0 + kL);  // lower end at 1 m
  s.v_mps = Eigen::Vector3d(0.2, 0.0, 5.0);
  const CatchPointPrediction p = gs::planning::predict_catch_point(s, 1.5, params);
  REQUIRE(p.found);
  // Up through 1.5 m (not a catch), apex, down through 1.5 m: the later root.
  const double t = (5.0 + std::sqrt(25.0 - 2 * kG * 0.5)) / kG;
  CHECK(p.t_s == Approx(t).margin(1e-8));
  CHECK(p.state.v_mps.z() < 0.0);
}
