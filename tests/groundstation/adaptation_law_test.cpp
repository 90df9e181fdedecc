// The adaptation law of Section VI (iterative means of the optimal catch point and of the
// catcher's offset bias) against direct means, the bias shift on the catch trajectory, and the
// after-throw evaluation of (42) from an observed flight against the model's catching instant.
#include "groundstation/adaptation/adaptation_law.hpp"

#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "adaptation_test_support.hpp"
#include "groundstation/adaptation/throw_evaluation.hpp"
#include "groundstation/model/impact.hpp"
#include "groundstation/planning/catch_point_predictor.hpp"
#include "groundstation/planning/catch_trajectory.hpp"
#include "groundstation/planning/catching_instant.hpp"

namespace {

using namespace gs::adaptation;
using gs::model::PoleParams;
using gs::model::PoleState;

AdaptationSettings test_settings(int window = 0) {
  AdaptationSettings s;
  s.nominal_catch_height_m = 1.40;
  s.nominal_waiting_xy_m = {0.70, 0.0};
  s.window = window;
  s.target_energy_J = gs::model::upright_energy_J(PoleParams{});
  return s;
}

ThrowRecord throw_with_optimal(double height_m, Eigen::Vector2d xy_m, ThrowOutcome outcome) {
  ThrowRecord r;
  r.outcome = outcome;
  r.optimal = OptimalCatch{0.8, height_m, xy_m};
  return r;
}

// The pole's free flight from a planar launch with a lateral offset, observed every 5 ms (the
// motion-capture rate) from the launch for `duration_s`, integrated with 1 ms steps.
std::vector<TimedPoleState> observed_flight(const PoleState& launch, double launch_t_s, double duration_s,
                                            const PoleParams& params) {
  std::vector<TimedPoleState> flight;
  PoleState s = launch;
  const int samples = static_cast<int>(std::floor(duration_s / 0.005 + 1e-9));
  for (int k = 0; k <= samples; ++k) {
    flight.push_back({launch_t_s + 0.005 * k, s});
    s = gs::model::propagate_pole(s, 0.005, 0.001, params);
  }
  return flight;
}

PoleState launch_pole(const gs::planning::PlanarLaunchState& launch, double y_m, double vy_mps,
                      const PoleParams& params) {
  PoleState s = gs::planning::pole_state_at_launch(launch, params);
  s.p_m.y() += y_m;
  s.v_mps.y() += vy_mps;
  return s;
}

}  // namespace

TEST_CASE("the iterative mean equals the direct mean of the samples (VI-A)") {
  std::mt19937 rng(42);
  std::normal_distribution<double> noise(0.0, 0.08);
  const AdaptationSettings settings = test_settings();
  AdaptationState state = initial_adaptation(settings);
  CHECK(state.catch_height_m == settings.nominal_catch_height_m);
  CHECK(state.waiting_xy_m == settings.nominal_waiting_xy_m);
  CHECK(state.catch_point_samples == 0);

  double sum_h = 0.0;
  Eigen::Vector2d sum_xy = Eigen::Vector2d::Zero();
  for (int k = 1; k <= 200; ++k) {
    const double h = 1.343 + noise(rng);
    const Eigen::Vector2d xy(0.64 + noise(rng), 0.1 + noise(rng));
    // Every outcome counts for the catch point: the pole's flight does not depend on the catch.
    const ThrowOutcome outcome = kAllThrowOutcomes[static_cast<std::size_t>(k) % 7];
    state = adapt(state, throw_with_optimal(h, xy, outcome), settings.window);
    sum_h += h;
    sum_xy += xy;
    REQUIRE(state.catch_point_samples == k);
    REQUIRE(state.catch_height_m == Approx(sum_h / k).epsilon(1e-13));
    REQUIRE((state.waiting_xy_m - sum_xy / k).norm() < 1e-13);
  }
  // The first sample replaces the nominal value outright.
  const AdaptationState one =
      adapt(initial_adaptation(settings), throw_with_optimal(1.2, {0.5, 0.2}, ThrowOutcome::throw_only), 0);
  CHECK(one.catch_height_m == 1.2);
  CHECK(one.waiting_xy_m == Eigen::Vector2d(0.5, 0.2));
}

TEST_CASE("a throw without an evaluated optimal instant leaves the catch point alone") {
  const AdaptationSettings settings = test_settings();
  AdaptationState state =
      adapt(initial_adaptation(settings), throw_with_optimal(1.3, {0.6, 0.1}, ThrowOutcome::caught), 0);
  ThrowRecord lost;  // e.g. the motion capture lost the pole
  lost.outcome = ThrowOutcome::missed;
  const AdaptationState after = adapt(state, lost, 0);
  CHECK(after == state);
}

TEST_CASE("with a window the gain stops at 1/N: the mean first, then exponential forgetting") {
  CHECK(iterative_mean_gain(0, 0) == 1.0);
  CHECK(iterative_mean_gain(9, 0) == Approx(0.1));
  CHECK(iterative_mean_gain(2, 5) == Approx(1.0 / 3.0));
  CHECK(iterative_mean_gain(50, 5) == Approx(0.2));

  const AdaptationSettings settings = test_settings(5);
  AdaptationState state = initial_adaptation(settings);
  // Five throws at 1.30 m: the plain mean of them.
  for (int k = 0; k < 5; ++k) {
    state = adapt(state, throw_with_optimal(1.30 + 0.01 * k, {0.6, 0.0}, ThrowOutcome::caught), 5);
  }
  CHECK(state.catch_height_m == Approx(1.32).epsilon(1e-12));
  // Then the throws move to 1.50 m: after n more the old offset has decayed by 0.8^n, whereas the
  // plain mean would still sit at the average of both groups.
  AdaptationState plain = recompute_adaptation(
      test_settings(0),
      std::vector<ThrowRecord>(5, throw_with_optimal(1.32, {0.6, 0.0}, ThrowOutcome::caught)));
  for (int n = 1; n <= 20; ++n) {
    const ThrowRecord shifted = throw_with_optimal(1.50, {0.6, 0.0}, ThrowOutcome::caught);
    state = adapt(state, shifted, 5);
    plain = adapt(plain, shifted, 0);
    REQUIRE(1.50 - state.catch_height_m == Approx((1.50 - 1.32) * std::pow(0.8, n)).epsilon(1e-9));
  }
  CHECK(1.50 - plain.catch_height_m == Approx(0.18 * 5.0 / 25.0).epsilon(1e-9));
}

TEST_CASE("the offset bias is the mean catcher error over catches that flew to the target (VI-B)") {
  const AdaptationSettings settings = test_settings();
  AdaptationState state = initial_adaptation(settings);
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  int samples = 0;
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.03);
  for (int k = 0; k < 70; ++k) {
    ThrowRecord r;
    r.outcome = kAllThrowOutcomes[static_cast<std::size_t>(k) % 7];
    r.target_xy_m = Eigen::Vector2d(0.6 + noise(rng), noise(rng));
    r.catcher_at_impact_xy_m = *r.target_xy_m + Eigen::Vector2d(0.05 + noise(rng), -0.02 + noise(rng));
    const AdaptationState next = adapt(state, r, 0);
    if (catcher_flew_to_target(r.outcome)) {
      sum += *r.catcher_at_impact_xy_m - *r.target_xy_m;
      ++samples;
      REQUIRE(next.bias_samples == samples);
      REQUIRE((next.offset_bias_m - sum / samples).norm() < 1e-14);
    } else {
      // Aborted and throw-only attempts: the vehicle was not at rest at its target.
      REQUIRE(next.offset_bias_m == state.offset_bias_m);
      REQUIRE(next.bias_samples == state.bias_samples);
    }
    state = next;
  }
  CHECK(samples == 40);
  CHECK(catcher_flew_to_target(ThrowOutcome::offset_practice));
  CHECK_FALSE(catcher_flew_to_target(ThrowOutcome::aborted_out_of_reach));
  CHECK_FALSE(catcher_flew_to_target(ThrowOutcome::throw_only));
  // A catch without the catcher's position measures nothing either.
  ThrowRecord unmeasured;
  unmeasured.outcome = ThrowOutcome::caught;
  unmeasured.target_xy_m = Eigen::Vector2d(0.6, 0.0);
  CHECK(adapt(state, unmeasured, 0) == state);
}

TEST_CASE("compensating the bias shifts the catch so the biased vehicle rests on the prediction") {
  // A catching vehicle that always comes to rest 8 cm ahead and 5 cm to the left of where it is
  // sent, plus noise. Each throw it is sent to the predicted point shifted by the bias in force.
  const Eigen::Vector2d true_bias(0.08, 0.05);
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, 0.01);
  std::normal_distribution<double> scatter(0.0, 0.15);
  AdaptationState state = initial_adaptation(test_settings());
  std::vector<double> miss_m;  // catcher vs prediction at the impact
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  for (int k = 0; k < 12; ++k) {
    ThrowRecord r;
    r.outcome = ThrowOutcome::caught;
    const Eigen::Vector2d predicted(0.64 + scatter(rng), scatter(rng));
    r.predicted = CatchPoint{predicted, 0.8};
    r.target_xy_m = compensate_offset_bias(predicted, state);
    REQUIRE((*r.target_xy_m - (predicted - state.offset_bias_m)).norm() == 0.0);
    r.catcher_at_impact_xy_m = *r.target_xy_m + true_bias + Eigen::Vector2d(noise(rng), noise(rng));
    miss_m.push_back((*r.catcher_at_impact_xy_m - predicted).norm());
    sum += *r.catcher_at_impact_xy_m - *r.target_xy_m;
    state = adapt(state, r, 0);
    // The bias is the mean of the vehicle's own errors, whatever shift was in force.
    REQUIRE((state.offset_bias_m - sum / (k + 1)).norm() < 1e-14);
  }
  CHECK((state.offset_bias_m - true_bias).norm() < 0.01);
  // The first catch misses the prediction by the whole bias; once adapted, by the noise only.
  CHECK(miss_m.front() > 0.8 * true_bias.norm());
  double late = 0.0;
  for (std::size_t k = 6; k < miss_m.size(); ++k) late += miss_m[k] / 6.0;
  CHECK(late < 0.3 * true_bias.norm());

  // The whole catch trajectory moves by minus the bias (VI-B), not only its end.
  gs::planning::CatchTrajectoryParams p;
  p.start_xy_m = {0.6, 0.0};
  p.target_xy_m = {0.85, -0.1};
  p.catch_height_m = 1.343;
  gs::planning::CatchTrajectoryParams shifted = p;
  shifted.start_xy_m = compensate_offset_bias(p.start_xy_m, state);
  shifted.target_xy_m = compensate_offset_bias(p.target_xy_m, state);
  const auto a = gs::planning::CatchTrajectory::create(p);
  const auto b = gs::planning::CatchTrajectory::create(shifted);
  REQUIRE(a);
  REQUIRE(b);
  REQUIRE(a->duration_s() == Approx(b->duration_s()));
  for (double t = 0.0; t <= a->duration_s(); t += 0.01) {
    const Eigen::Vector3d d = b->reference(t).position_m - a->reference(t).position_m;
    REQUIRE((d.head<2>() + state.offset_bias_m).norm() < 1e-12);
    REQUIRE(std::abs(d.z()) < 1e-12);
  }
}

TEST_CASE("recomputing from the records gives the incremental values bit for bit") {
  const AdaptationSettings settings = test_settings(4);
  std::vector<ThrowRecord> records;
  AdaptationState incremental = initial_adaptation(settings);
  for (int id = 1; id <= 60; ++id) {
    records.push_back(adaptation_test::make_record(id));
    incremental = adapt(incremental, records.back(), settings.window);
  }
  CHECK(recompute_adaptation(settings, records) == incremental);
  CHECK(incremental.catch_point_samples > 0);
  CHECK(incremental.bias_samples > 0);
}

TEST_CASE("records with non-finite figures are rejected by validate") {
  ThrowRecord r = adaptation_test::make_record(12);
  CHECK(validate(r).empty());
  r.launch.vz_mps = std::nan("");
  CHECK(validate(r) == "launch.vz_mps is not finite");
  r = adaptation_test::make_record(12);
  r.optimal = OptimalCatch{0.8, INFINITY, {0.0, 0.0}};
  CHECK(validate(r) == "optimal.height_m is not finite");
  for (const ThrowOutcome o : kAllThrowOutcomes) CHECK(parse_throw_outcome(to_string(o)) == o);
  CHECK_FALSE(parse_throw_outcome("caught "));
}

TEST_CASE("the optimal catch (42) evaluated from an observed flight matches the model's instant") {
  const PoleParams params;
  std::mt19937 rng(5);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int trial = 0; trial < 6; ++trial) {
    gs::planning::PlanarLaunchState launch = gs::planning::fig5_launch_state();
    launch.x_m += 0.02 * n(rng);
    launch.vx_mps += 0.05 * n(rng);
    launch.vz_mps += 0.05 * n(rng);
    launch.alpha_rad += 0.02 * n(rng);
    launch.alpha_dot_radps += 0.1 * n(rng);
    const PoleState pole = launch_pole(launch, 0.02 * n(rng), 0.05 * n(rng), params);
    const auto model = gs::planning::find_catching_instant(pole, params);
    REQUIRE(model.found);
    const double t0 = 100.0 + trial;  // launch time on the ground clock

    // Observed past the instant: found between samples, interpolated.
    const auto flight = observed_flight(pole, t0, model.t_s + 0.1, params);
    const auto observed = evaluate_optimal_catch(flight, t0, params);
    REQUIRE(observed);
    CHECK_FALSE(observed->extrapolated);
    CHECK(observed->point.t_s == Approx(model.t_s).margin(2e-4));
    CHECK(observed->point.height_m == Approx(model.catch_height_m).margin(1e-3));
    CHECK((observed->point.xy_m - model.catch_point_m).norm() < 1e-3);

    // Caught before (42) was met (higher than optimal): continued with the model.
    const auto truncated = observed_flight(pole, t0, model.t_s - 0.1, params);
    const auto continued = evaluate_optimal_catch(truncated, t0, params);
    REQUIRE(continued);
    CHECK(continued->extrapolated);
    CHECK(continued->point.t_s == Approx(model.t_s).margin(1e-6));
    CHECK(continued->point.height_m == Approx(model.catch_height_m).margin(1e-5));

    // The actual catch point: where the observed lower end crosses the height used.
    const double height_used = model.catch_height_m + 0.05;
    const auto crossing = lower_end_crossing(flight, height_used, t0, params);
    const auto predicted = gs::planning::predict_catch_point(pole, height_used, params);
    REQUIRE(crossing);
    REQUIRE(predicted.found);
    CHECK(crossing->t_s == Approx(predicted.t_s).margin(2e-4));
    CHECK((crossing->xy_m - Eigen::Vector2d(predicted.x_m, predicted.y_m)).norm() < 1e-3);
  }
  // Nothing observed, or times that do not increase: no evaluation.
  CHECK_FALSE(evaluate_optimal_catch({}, 0.0, params));
  const PoleState pole = gs::planning::pole_state_at_launch(gs::planning::fig5_launch_state(), params);
  const std::vector<TimedPoleState> backwards = {{1.0, pole}, {0.5, pole}};
  CHECK_FALSE(evaluate_optimal_catch(backwards, 0.0, params));
  CHECK_FALSE(lower_end_crossing(backwards, 1.0, 0.0, params));
}

TEST_CASE("the energy after a catch at the optimal instant is E* (41), for a moving plate too") {
  const PoleParams params;
  const PoleState launch = gs::planning::pole_state_at_launch(gs::planning::fig5_launch_state(), params);
  const auto instant = gs::planning::find_catching_instant(launch, params);
  REQUIRE(instant.found);
  const double e_star = gs::model::upright_energy_J(params);
  CHECK(post_impact_energy_J(instant.pole, Eigen::Vector3d::Zero(), params) == Approx(e_star).epsilon(1e-6));
  // The planar formula (40), (41) for the same pole.
  const auto k = gs::model::planar_kinematics_from_lower_end(instant.pole);
  CHECK(post_impact_energy_J(instant.pole, Eigen::Vector3d::Zero(), params) ==
        Approx(gs::model::pivoted_pole_energy_J(k.alpha_rad, gs::model::post_impact_rate_radps(k, params),
                                                params))
            .epsilon(1e-12));
  // Only the velocity relative to the plate matters.
  const Eigen::Vector3d plate(0.3, -0.2, 0.4);
  PoleState moving = instant.pole;
  moving.v_mps += plate;
  CHECK(post_impact_energy_J(moving, plate, params) ==
        Approx(post_impact_energy_J(instant.pole, Eigen::Vector3d::Zero(), params)).epsilon(1e-12));
  // Caught 0.05 s early the pole has not yet the right energy.
  const PoleState early = gs::model::propagate_pole(launch, instant.t_s - 0.05, 0.001, params);
  CHECK(std::abs(post_impact_energy_J(early, Eigen::Vector3d::Zero(), params) - e_star) > 1e-3);
}

TEST_CASE("a series like the paper's: adapted catch point = mean of the evaluated optimal points") {
  // Nine throws around the Fig. 5 launch state (scatter chosen, the paper does not give it):
  // throw 1 adapts only, 2-7 practice with a 1 m offset (2 and 7 aborted), 8-9 are caught.
  const PoleParams params;
  const AdaptationSettings settings = nominal_adaptation_settings(params);
  REQUIRE(validate(settings).empty());
  std::mt19937 rng(2013);
  std::normal_distribution<double> n(0.0, 1.0);
  AdaptationState state = initial_adaptation(settings);
  const Eigen::Vector2d catcher_bias(0.04, -0.03);
  double sum_h = 0.0;
  Eigen::Vector2d sum_xy = Eigen::Vector2d::Zero();
  std::printf("series: nominal catch height %.4f m at (%.4f, %.4f) m, E* = %.4f J\n",
              settings.nominal_catch_height_m, settings.nominal_waiting_xy_m.x(),
              settings.nominal_waiting_xy_m.y(), settings.target_energy_J);
  std::printf("  k  outcome               h_opt    h_used   travel_m  |E-E*|_J   h_adapted  bias\n");
  for (int k = 1; k <= 9; ++k) {
    gs::planning::PlanarLaunchState launch = gs::planning::fig5_launch_state();
    launch.x_m += 0.01 * n(rng);
    launch.z_m += 0.01 * n(rng);
    launch.vx_mps += 0.03 * n(rng);
    launch.vz_mps += 0.03 * n(rng);
    launch.alpha_rad += 0.01 * n(rng);
    launch.alpha_dot_radps += 0.03 * n(rng);
    const double y = 0.02 * n(rng);
    const double vy = 0.05 * n(rng);
    const PoleState pole = launch_pole(launch, y, vy, params);
    const auto model = gs::planning::find_catching_instant(pole, params);
    REQUIRE(model.found);
    const auto flight = observed_flight(pole, 0.0, model.t_s + 0.3, params);

    ThrowRecord r;
    r.outcome = k == 1               ? ThrowOutcome::throw_only
                : (k == 2 || k == 7) ? ThrowOutcome::aborted_out_of_reach
                : k <= 7             ? ThrowOutcome::offset_practice
                                     : ThrowOutcome::caught;
    r.launch = launch;
    r.launch_y_m = y;
    r.launch_vy_mps = vy;
    r.catch_height_used_m = state.catch_height_m;
    r.waiting_xy_m = state.waiting_xy_m;
    const auto actual = lower_end_crossing(flight, r.catch_height_used_m, 0.0, params);
    REQUIRE(actual);
    r.actual = *actual;
    r.predicted = *actual;  // a converged prediction
    const auto optimal = evaluate_optimal_catch(flight, 0.0, params);
    REQUIRE(optimal);
    r.optimal = optimal->point;
    const Eigen::Vector2d offset =
        r.outcome == ThrowOutcome::offset_practice ? Eigen::Vector2d(1.0, 0.0) : Eigen::Vector2d::Zero();
    if (catcher_flew_to_target(r.outcome)) {
      r.target_xy_m = compensate_offset_bias(actual->xy_m, state) + offset;
      r.catcher_at_impact_xy_m = *r.target_xy_m + catcher_bias;
    }
    double energy_error = NAN;
    if (r.outcome == ThrowOutcome::caught) {
      // The pole state where it meets the plate at the height used.
      const PoleState at_impact = gs::model::propagate_pole(pole, actual->t_s, 0.001, params);
      r.energy_after_impact_J = post_impact_energy_J(at_impact, Eigen::Vector3d::Zero(), params);
      energy_error = std::abs(*r.energy_after_impact_J - settings.target_energy_J);
    }
    const double travel = (actual->xy_m - r.waiting_xy_m).norm();
    state = adapt(state, r, settings.window);
    sum_h += optimal->point.height_m;
    sum_xy += optimal->point.xy_m;
    char energy[16] = "-";
    if (std::isfinite(energy_error)) std::snprintf(energy, sizeof energy, "%.5f", energy_error);
    std::printf("  %d  %-20s  %.4f  %.4f  %.4f    %-8s   %.4f     (%+.3f, %+.3f)\n", k,
                std::string(to_string(r.outcome)).c_str(), optimal->point.height_m, r.catch_height_used_m,
                travel, energy, state.catch_height_m, state.offset_bias_m.x(), state.offset_bias_m.y());
    REQUIRE(state.catch_height_m == Approx(sum_h / k).epsilon(1e-13));
    REQUIRE((state.waiting_xy_m - sum_xy / k).norm() < 1e-13);
  }
  // The bias rests on throws 3-6 and 8-9 (practice and catches), not 1, 2, 7.
  CHECK(state.bias_samples == 6);
  CHECK((state.offset_bias_m - catcher_bias).norm() < 1e-12);
}
