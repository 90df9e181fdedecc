// The estimator on the HIL truth plant's scenarios (hil/plant/scenario_runner.hpp): a plant
// written apart from the ground station's models, with compliant plate contact, a pole with a
// real tube's inertia, a 20-segment drag quadrature and motion capture with latency. Its vehicles
// are flown by the plant's own controllers, whose commands are not recorded: the estimator runs
// here as in an offline replay, without commands. Measurements are stamped with their capture
// time (the motion-capture system's clock), as the ground station does.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "groundstation/estimation/state_estimator.hpp"
#include "groundstation/planning/catch_point_predictor.hpp"
#include "hil/plant/scenario_runner.hpp"

namespace {

using gs::estimation::MocapFrame;
using gs::estimation::PoleMode;
using gs::estimation::StateEstimator;

constexpr double kFrame_s = 0.005;

hil::ScenarioResult run_scenario(const std::string& name, hil::Scenario& scenario) {
  std::string error;
  const bool loaded = hil::load_scenario(hil::scenario_directory() + "/" + name, scenario, error);
  INFO(error);
  REQUIRE(loaded);
  hil::ScenarioResult result;
  const bool ran = hil::run_scenario(scenario, result, error);
  INFO(error);
  REQUIRE(ran);
  return result;
}

// The motion-capture rows grouped into frames by capture time.
std::vector<MocapFrame> frames(const hil::ScenarioResult& r) {
  std::vector<MocapFrame> out;
  for (const hil::MocapRow& row : r.mocap) {
    if (out.empty() || std::abs(out.back().t_s - row.capture_t_s) > 1e-9) {
      out.emplace_back();
      out.back().t_s = row.capture_t_s;
    }
    gs::estimation::MocapPose pose;
    pose.p_m = row.position_m;
    pose.q = row.attitude;
    if (row.body == hil::Body::pole) {
      out.back().pole = pose;
    } else {
      out.back().vehicle[row.body == hil::Body::vehicle2 ? 1 : 0] = pose;
    }
  }
  return out;
}

// The true pole at a time (the nearest plant tick), in the free-flight state's convention.
gs::model::PoleState truth_at(const hil::ScenarioResult& r, double t_s) {
  const auto it = std::lower_bound(r.pole_truth.begin(), r.pole_truth.end(), t_s,
                                   [](const hil::PoleTruthRow& row, double t) { return row.t_s < t - 1e-9; });
  const hil::PoleTruthRow& row = it == r.pole_truth.end() ? r.pole_truth.back() : *it;
  gs::model::PoleState s;
  s.p_m = row.position_m;
  s.v_mps = row.velocity_mps;
  s.n = row.axis;
  s.omega_radps = row.rate_radps;
  return gs::model::normalised_pole_state(s);  // the tube's spin about its axis is not estimated
}

struct Crossing {
  double t_s = 0.0;
  Eigen::Vector3d end = Eigen::Vector3d::Zero();
};

// The true pole's lowest end coming down through a height after t0.
std::optional<Crossing> true_crossing(const hil::ScenarioResult& r, double t0, double height,
                                      double half_length) {
  std::optional<Eigen::Vector3d> previous;
  double previous_t = 0.0;
  for (const hil::PoleTruthRow& row : r.pole_truth) {
    if (row.t_s < t0) continue;
    const Eigen::Vector3d a = row.position_m - half_length * row.axis;
    const Eigen::Vector3d b = row.position_m + half_length * row.axis;
    const Eigen::Vector3d low = a.z() < b.z() ? a : b;
    if (previous && previous->z() > height && low.z() <= height) {
      const double f = (previous->z() - height) / (previous->z() - low.z());
      return Crossing{previous_t + f * (row.t_s - previous_t), *previous + f * (low - *previous)};
    }
    previous = low;
    previous_t = row.t_s;
  }
  return std::nullopt;
}

}  // namespace

TEST_CASE("HIL plant: a thrown pole is tracked from launch to the catch", "[estimation][hil]") {
  hil::Scenario scenario;
  const hil::ScenarioResult r = run_scenario("free_flight_catch.yaml", scenario);
  REQUIRE(r.launch_t_s);
  REQUIRE(r.impact_t_s);
  REQUIRE(r.impact_on == hil::Contact::vehicle2);
  const double catch_height = scenario.catch_height_m;
  const std::optional<Crossing> crossing =
      true_crossing(r, *r.launch_t_s, catch_height, r.config.pole.half_length_m);
  REQUIRE(crossing);

  StateEstimator est;
  std::optional<double> launch_detected;
  std::optional<double> impact_detected;
  double catch_error_early = -1.0;
  double catch_error_late = -1.0;
  double nees_sum = 0.0;
  int nees_n = 0;
  int switches_in_flight = 0;
  for (const MocapFrame& f : frames(r)) {
    const std::uint64_t before = est.switch_count();
    est.update(f);
    const double t = f.t_s;
    if (est.switch_count() != before && t > *r.launch_t_s + 0.05 && t < *r.impact_t_s - 0.01) {
      ++switches_in_flight;
    }
    if (!launch_detected && t >= *r.launch_t_s - 0.05 && est.mode() == PoleMode::free) {
      launch_detected = t;
    }
    if (!impact_detected && est.mode() == PoleMode::on_vehicle2) impact_detected = t;
    if (est.mode() != PoleMode::free) continue;
    const auto predict = [&]() {
      const gs::planning::CatchPointPrediction p =
          gs::planning::predict_catch_point(est.pole().state, catch_height, est.pole_model());
      return p.found ? std::hypot(p.x_m - crossing->end.x(), p.y_m - crossing->end.y()) : 1e9;
    };
    if (catch_error_early < 0.0 && t >= *r.launch_t_s + 0.1 - 1e-9) catch_error_early = predict();
    if (catch_error_late < 0.0 && t >= crossing->t_s - 0.15 - 1e-9) catch_error_late = predict();
    if (t > *r.launch_t_s + 0.05 && t < *r.impact_t_s - 0.01) {
      nees_sum += gs::estimation::free_flight_nees(est.free_flight_filter(), truth_at(r, t));
      ++nees_n;
    }
  }
  REQUIRE(launch_detected);
  REQUIRE(impact_detected);
  std::printf("HIL free_flight_catch (no commands): launch detected %+.1f frames from the truth, "
              "impact %+.1f frames; catch point %.1f mm off at launch + 0.1 s, %.1f mm 0.15 s "
              "before the crossing; mean NEES %.2f (10 dof) over %d frames; %d switches in "
              "flight\n",
              (*launch_detected - *r.launch_t_s) / kFrame_s, (*impact_detected - *r.impact_t_s) / kFrame_s,
              1e3 * catch_error_early, 1e3 * catch_error_late, nees_sum / nees_n, nees_n, switches_in_flight);
  CHECK(switches_in_flight == 0);
  CHECK(std::abs(*impact_detected - *r.impact_t_s) <= 2 * kFrame_s + 1e-9);
  CHECK(catch_error_late < 0.02);
}

TEST_CASE("HIL plant: no mode switch while vehicle 1 balances the pole", "[estimation][hil]") {
  hil::Scenario scenario;
  const hil::ScenarioResult r = run_scenario("balanced_hover.yaml", scenario);
  StateEstimator est;
  double max_error = 0.0;
  for (const MocapFrame& f : frames(r)) {
    est.update(f);
    if (f.t_s > 0.5 && f.pole) {
      max_error = std::max(max_error, (est.pole().state.p_m - truth_at(r, f.t_s).p_m).norm());
    }
  }
  const gs::estimation::EstimatorHealth h = est.health(est.time());
  std::printf("HIL balanced_hover (no commands): %llu switches (1 = the initial mode) in %.1f s, "
              "mode %s, max pole position error %.2f mm, pole NIS mean %.2f\n",
              static_cast<unsigned long long>(est.switch_count()), est.time(),
              std::string(gs::estimation::pole_mode_name(est.mode())).c_str(), 1e3 * max_error,
              h.pole.mean_nis);
  CHECK(est.switch_count() == 1);
  CHECK(est.mode() == PoleMode::on_vehicle1);
  CHECK(max_error < 0.01);
}
