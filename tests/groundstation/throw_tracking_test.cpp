// Time-varying LQR tracking of the planned throw: the gains' terminal condition, and the closed
// loop on the planar model from a perturbed start, sampled like the ground station (200 Hz,
// zero-order hold, inputs saturated at the limits).
#include "groundstation/planning/throw_tracking.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>

#include "groundstation/planning/throw_planner.hpp"

namespace {

using gs::model::PlanarInput;
using gs::model::PlanarState;
using gs::planning::ThrowProblem;
namespace planar = gs::model::planar;

const gs::planning::ThrowPlan& paper_plan() {
  static const gs::planning::ThrowPlan plan = gs::planning::plan_throw(ThrowProblem{});
  return plan;
}

struct Flight {
  PlanarState<double> end;
  double min_normal_force_mps2 = 1e9;        // over [0, T - 0.1 s]
  double min_normal_force_final_mps2 = 1e9;  // over [T - 0.1 s, T - 5 ms], where the plan's F_N
                                             // falls smoothly to 0 (the input slew limits)
};

// RK4 in 0.1 ms steps; the input is recomputed every 5 ms and held in between.
template <typename Controller>
Flight fly(const PlanarState<double>& start, const ThrowProblem& problem, Controller&& control) {
  Flight flight;
  PlanarState<double> s = start;
  const double h = 1e-4;
  const int steps = static_cast<int>(std::lround(problem.duration_s / h));
  PlanarInput<double> u = PlanarInput<double>::Zero();
  for (int k = 0; k < steps; ++k) {
    const double t = k * h;
    if (k % 50 == 0) u = gs::planning::saturate(control(t, s), problem.limits);
    const auto f = [&](const PlanarState<double>& x) {
      return gs::model::planar_pole_vehicle_dynamics<double>(x, u);
    };
    const PlanarState<double> k1 = f(s);
    const PlanarState<double> k2 = f(s + 0.5 * h * k1);
    const PlanarState<double> k3 = f(s + 0.5 * h * k2);
    const PlanarState<double> k4 = f(s + h * k3);
    s += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    const double fn = gs::model::planar_normal_force_per_mass_mps2<double>(s, u);
    if (t + h <= problem.duration_s - 0.1) {
      flight.min_normal_force_mps2 = std::min(flight.min_normal_force_mps2, fn);
    } else if (t + h <= problem.duration_s - 0.005) {
      flight.min_normal_force_final_mps2 = std::min(flight.min_normal_force_final_mps2, fn);
    }
  }
  flight.end = s;
  return flight;
}

PlanarState<double> perturbed_start() {
  PlanarState<double> s = PlanarState<double>::Zero();
  s(planar::kX) = 0.05;
  s(planar::kZ) = -0.05;
  s(planar::kAlpha) = 2.0 * M_PI / 180.0;
  return s;
}

}  // namespace

TEST_CASE("the throw's TV-LQR gains end at R^-1 B^T Q_f", "[throw_tracking]") {
  REQUIRE(paper_plan().success);
  const gs::planning::ThrowTrackingWeights weights;
  const gs::planning::ThrowTracker tracker(paper_plan().trajectory, weights);
  REQUIRE(tracker.valid());
  const ThrowProblem problem;
  const auto lin = gs::model::linearise_planar_pole_vehicle(problem.launch_state, problem.launch_input());
  const Eigen::MatrixXd expected = weights.R().inverse() * lin.B.transpose() * weights.Qfinal();
  CHECK((tracker.gain(problem.duration_s) - expected).cwiseAbs().maxCoeff() < 1e-9);
  // The gains are stored on the 5 ms grid over [0, T].
  CHECK(tracker.gains().times_s().front() == 0.0);
  CHECK(tracker.gains().times_s().back() == problem.duration_s);
  CHECK(tracker.gains().times_s().size() == 501);
  // Far from T the gains have left the terminal value (the Riccati equation was integrated).
  CHECK((tracker.gain(1.0) - expected).cwiseAbs().maxCoeff() > 1.0);
}

TEST_CASE("on the nominal start the tracker reproduces the planned inputs", "[throw_tracking]") {
  REQUIRE(paper_plan().success);
  const gs::planning::ThrowTracker tracker(paper_plan().trajectory);
  REQUIRE(tracker.valid());
  const auto& ref = tracker.reference();
  for (double t : {0.0, 0.7, 1.3, 2.2, 2.5}) {
    CHECK((tracker.command(t, ref.state_at(t)) - ref.input_at(t)).norm() < 1e-12);
  }
}

TEST_CASE("a feed-forward lead reads the planned inputs ahead, held at the throw's end", "[throw_tracking]") {
  REQUIRE(paper_plan().success);
  const gs::planning::ThrowTracker tracker(paper_plan().trajectory);
  REQUIRE(tracker.valid());
  const auto& ref = tracker.reference();
  const double T = ref.duration_s();
  const double lead = 0.03;
  // On the reference the feedback is zero: the command is the plan's input `lead` later.
  for (double t : {0.0, 0.7, 1.3, 2.2}) {
    CHECK((tracker.command(t, ref.state_at(t), lead) - ref.input_at(t + lead)).norm() < 1e-12);
  }
  // Within `lead` of T it is the plan's last input: the thrust cut comes `lead` earlier.
  CHECK((tracker.command(T - 0.01, ref.state_at(T - 0.01), lead) - ref.input_at(T)).norm() < 1e-12);
  CHECK(ref.input_at(T)(planar::kThrust) < ref.input_at(T - 0.1)(planar::kThrust) - 5.0);
  // The feedback is the same with and without it; a negative lead counts as none.
  PlanarState<double> off = ref.state_at(1.3);
  off(0) += 0.05;
  const PlanarInput<double> feedback = tracker.command(1.3, off) - ref.input_at(1.3);
  CHECK((tracker.command(1.3, off, lead) - ref.input_at(1.3 + lead) - feedback).norm() < 1e-12);
  CHECK(tracker.command(1.3, off, -lead) == tracker.command(1.3, off));
}

TEST_CASE("the TV-LQR brings a perturbed throw to the launch state", "[throw_tracking]") {
  const ThrowProblem problem;
  REQUIRE(paper_plan().success);
  const gs::planning::ThrowTracker tracker(paper_plan().trajectory);
  REQUIRE(tracker.valid());
  const PlanarState<double> start = perturbed_start();

  // Open loop from the perturbed start the pole falls off: what the feedback is for.
  const Flight open = fly(
      start, problem, [&](double t, const PlanarState<double>&) { return tracker.reference().input_at(t); });
  CHECK(std::abs(open.end(planar::kAlpha) - problem.launch_state(planar::kAlpha)) > 0.5);

  const Flight closed =
      fly(start, problem, [&](double t, const PlanarState<double>& s) { return tracker.command(t, s); });
  const PlanarState<double> err = closed.end - problem.launch_state;
  INFO("end-state error " << err.transpose());
  // Measured: about 0.5 mm, 1.2 cm/s, 2e-3 rad of pitch, 1e-4 rad of tilt, 6e-3 rad/s.
  CHECK(err.head<2>().cwiseAbs().maxCoeff() < 0.005);
  CHECK(err.segment<2>(planar::kVx).cwiseAbs().maxCoeff() < 0.05);
  CHECK(std::abs(err(planar::kTheta)) < 0.01);
  CHECK(std::abs(err(planar::kAlpha)) < 0.005);
  CHECK(std::abs(err(planar::kAlphaDot)) < 0.03);
  // The pole stayed on the plate on the way: pressed firmly, then to the end.
  CHECK(closed.min_normal_force_mps2 > 2.0);
  CHECK(closed.min_normal_force_final_mps2 > 0.0);
}
