// The throw book (groundstation/planning/throw_book.hpp): the Fig. 5 throw planned and tracked
// at construction, throws to targets aimed against the miss learnt, and what it refuses.
#include <catch2/catch.hpp>

#include <stdexcept>

#include "groundstation/planning/throw_book.hpp"

namespace {

using gs::planning::ThrowBook;

const gs::model::VehicleLimits kLimits{1.0, 20.0, 10.0};

}  // namespace

TEST_CASE("The book plans the Fig. 5 throw and its TV-LQR, or refuses limits it cannot fly") {
  const ThrowBook book(kLimits, {});
  CHECK(book.plan().success);
  CHECK(book.tracker().valid());
  CHECK(book.plan().trajectory.duration_s() == Approx(book.problem().duration_s));
  // Thrust that cannot hold the vehicle up: no throw.
  CHECK_THROWS_AS(ThrowBook(gs::model::VehicleLimits{1.0, 5.0, 10.0}, {}), std::runtime_error);
}

TEST_CASE("A Fig. 5 throw planned for the same limits and weights is shared, another is planned anew") {
  const auto planned = gs::planning::plan_fig5_throw(kLimits, {});
  const ThrowBook shared(kLimits, {}, planned);
  CHECK(shared.fig5() == planned);
  CHECK(&shared.tracker() == &planned->tracker);
  const ThrowBook own(kLimits, {});
  CHECK(own.plan().trajectory.duration_s() == planned->plan.trajectory.duration_s());
  // Planned for other limits, or other weights: not this book's throw.
  const gs::model::VehicleLimits slower{1.0, 20.0, 8.0};
  const ThrowBook other_limits(slower, {}, planned);
  CHECK(other_limits.fig5() != planned);
  CHECK(other_limits.fig5()->limits == slower);
  gs::planning::ThrowTrackingWeights heavier;
  heavier.terminal_factor = 2.0;
  const ThrowBook other_weights(kLimits, heavier, planned);
  CHECK(other_weights.fig5() != planned);
  CHECK(other_weights.fig5()->weights == heavier);
}

TEST_CASE("A throw to a target comes down on the point aimed at, against the miss learnt") {
  ThrowBook book(kLimits, {});
  const Eigen::Vector3d origin(0.0, 0.0, 2.0), target(0.0, 3.5, 1.3);
  const std::optional<gs::planning::TargetThrow> plain =
      book.plan_to(origin, target, Eigen::Vector3d::Zero());
  REQUIRE(plain);
  CHECK(plain->target_m == target);
  CHECK(plain->tracker.valid());
  CHECK((plain->plan.target_m - target).norm() < 1e-9);
  CHECK(plain->plan.yaw_rad == Approx(M_PI / 2));
  // Throws came down 0.2 m long: the next is aimed 0.2 m short, along the throw's direction (+y).
  const auto aimed = book.plan_to(origin, target, Eigen::Vector3d(0.2, 0.0, 0.0));
  REQUIRE(aimed);
  CHECK(aimed->target_m == target);
  CHECK((aimed->plan.target_m - (target - Eigen::Vector3d(0.0, 0.2, 0.0))).norm() < 1e-9);
  // Beyond the planner's span: refused.
  CHECK_FALSE(book.plan_to(origin, Eigen::Vector3d(0.0, 9.0, 1.3), Eigen::Vector3d::Zero()));
}
