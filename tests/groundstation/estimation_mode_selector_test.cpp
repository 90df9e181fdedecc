// The CUSUM mode selection of the hybrid pole estimator (estimation/mode_selector.hpp) and the
// mode names.
#include "groundstation/estimation/mode_selector.hpp"

#include <catch2/catch.hpp>

namespace {

using gs::estimation::ModeSelector;
using gs::estimation::PoleMode;
using LogLikelihoods = std::array<std::optional<double>, gs::estimation::kPoleModeCount>;
using Favoured = std::array<bool, gs::estimation::kPoleModeCount>;

}  // namespace

TEST_CASE("a candidate that explains the data better wins after enough evidence", "[estimation]") {
  ModeSelector s;  // threshold 12, cap 7
  s.reset(PoleMode::on_vehicle1);
  // Free flight 3 nats better per frame: 3, 6, 9, 12 -> the fourth frame switches.
  for (int k = 0; k < 3; ++k) {
    CHECK_FALSE(s.step(LogLikelihoods{-5.0, -8.0, std::nullopt}, Favoured{}));
    CHECK(s.accumulating(PoleMode::free));
  }
  CHECK(s.statistic(PoleMode::free) == Approx(9.0));
  const auto chosen = s.step(LogLikelihoods{-5.0, -8.0, std::nullopt}, Favoured{});
  REQUIRE(chosen);
  CHECK(*chosen == PoleMode::free);
  CHECK(s.active() == PoleMode::free);
  CHECK(s.statistic(PoleMode::free) == 0.0);
}

TEST_CASE("equal or worse candidates never win, and the statistic restarts at zero", "[estimation]") {
  ModeSelector s;
  s.reset(PoleMode::on_vehicle1);
  for (int k = 0; k < 1000; ++k) {
    const double noise = (k % 7) - 3.0;  // zero-mean wobble of the log-likelihood ratio
    CHECK_FALSE(s.step(LogLikelihoods{-5.0 + 0.5 * noise - 0.5, -5.0, std::nullopt}, Favoured{}));
  }
  // A worse run drives the statistic to zero: the candidate is re-seeded (not accumulating).
  s.step(LogLikelihoods{-20.0, -5.0, std::nullopt}, Favoured{});
  CHECK_FALSE(s.accumulating(PoleMode::free));
}

TEST_CASE("one corrupted frame cannot switch on its own", "[estimation]") {
  ModeSelector s;
  s.reset(PoleMode::free);
  CHECK_FALSE(s.step(LogLikelihoods{-1000.0, -5.0, std::nullopt}, Favoured{}));
  CHECK(s.statistic(PoleMode::on_vehicle1) == Approx(7.0));  // capped
  // A second frame in favour does.
  const auto chosen = s.step(LogLikelihoods{-1000.0, -5.0, std::nullopt}, Favoured{});
  REQUIRE(chosen);
  CHECK(*chosen == PoleMode::on_vehicle1);
}

TEST_CASE("evidence from elsewhere lowers the threshold of a mode", "[estimation]") {
  ModeSelector s;
  s.reset(PoleMode::free);
  Favoured favoured{};
  favoured[gs::estimation::mode_index(PoleMode::on_vehicle2)] = true;
  const LogLikelihoods ll{-10.0, std::nullopt, -5.0};
  const auto chosen = s.step(ll, favoured);  // 5 nats >= the favoured threshold of 4
  REQUIRE(chosen);
  CHECK(*chosen == PoleMode::on_vehicle2);
  ModeSelector t;
  t.reset(PoleMode::free);
  CHECK_FALSE(t.step(ll, Favoured{}));
}

TEST_CASE("the pole cannot pass between vehicles without flying", "[estimation]") {
  ModeSelector s;
  s.reset(PoleMode::on_vehicle1);
  for (int k = 0; k < 10; ++k) {
    CHECK_FALSE(s.step(LogLikelihoods{std::nullopt, -50.0, -5.0}, Favoured{}));
  }
  CHECK(s.statistic(PoleMode::on_vehicle2) == 0.0);
  CHECK_FALSE(gs::estimation::pole_mode_transition_allowed(PoleMode::on_vehicle1, PoleMode::on_vehicle2));
  CHECK(gs::estimation::pole_mode_transition_allowed(PoleMode::on_vehicle2, PoleMode::free));
  // Without the active mode's likelihood nothing is decided.
  CHECK_FALSE(s.step(LogLikelihoods{-1.0, std::nullopt, std::nullopt}, Favoured{}));
}

TEST_CASE("mode names", "[estimation]") {
  for (PoleMode m : gs::estimation::kPoleModes) {
    CHECK(gs::estimation::pole_mode_from_name(gs::estimation::pole_mode_name(m)) == m);
  }
  CHECK(gs::estimation::pole_mode_name(PoleMode::on_vehicle2) == "on_vehicle2");
  CHECK_FALSE(gs::estimation::pole_mode_from_name("vehicle3"));
}
